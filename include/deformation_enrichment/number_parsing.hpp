#pragma once
// Strict parsing of one text token as a number, shared by the text readers (TetGen, plan CSV). The whole
// token must be the number: std::stod / std::stol stop at the first bad character and skip leading blanks,
// so "1.5x" or "2,5" would read as 1.5 and 2. std::from_chars is locale-independent and throws nothing.
#include <charconv>
#include <optional>
#include <string_view>
#include <system_error>

namespace deformation_enrichment {

namespace detail {
// from_chars takes no '+'; accept one in front of a digit or '.' as strtod does ("+-1" stays invalid).
inline std::string_view withoutPlus(std::string_view token) {
  if (token.size() > 1 && token[0] == '+' && token[1] != '-' && token[1] != '+') token.remove_prefix(1);
  return token;
}

template <class T>
std::optional<T> parseWhole(std::string_view token) {
  token = withoutPlus(token);
  T value{};
  const char* end = token.data() + token.size();
  const auto [stop, error] = std::from_chars(token.data(), end, value);
  if (token.empty() || error != std::errc() || stop != end) return std::nullopt;
  return value;
}
}  // namespace detail

/// A decimal integer with an optional sign ("12", "+12", "-3"); nullopt for anything else, including
/// surrounding blanks, trailing text and values outside long's range.
inline std::optional<long> parseInteger(std::string_view token) { return detail::parseWhole<long>(token); }

/// A decimal floating-point number with an optional sign ("1", "-2.5e-3", "+.5"), or "inf" / "nan";
/// nullopt for anything else, including surrounding blanks, trailing text and magnitudes that overflow or
/// underflow double. Callers that need finite values check std::isfinite (to name that problem).
inline std::optional<double> parseReal(std::string_view token) { return detail::parseWhole<double>(token); }

}  // namespace deformation_enrichment
