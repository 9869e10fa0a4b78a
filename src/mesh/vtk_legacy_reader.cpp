#include "vtk_legacy_reader.hpp"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstring>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/number_parsing.hpp"

namespace deformation_enrichment::mesh::detail {
namespace {

std::string upper(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return std::toupper(c); });
  return text;
}

bool isSpace(char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; }

/// Bytes of one binary value of a legacy data type (big-endian on disk); 0 for types not read here.
std::size_t typeSize(const std::string& type) {
  if (type == "float" || type == "int" || type == "vtktypeint32") return 4;
  if (type == "double" || type == "vtktypeint64") return 8;
  return 0;
}

/// Reading position in a legacy file: keywords and counts are text; data is text (ASCII) or big-endian
/// binary values right after its section's header line (BINARY).
class LegacyCursor {
public:
  LegacyCursor(const std::string& bytes, std::string name) : bytes_(bytes), name_(std::move(name)) {}

  bool binary = false;

  /// The rest of the current line, without its newline; moves past it.
  std::string line() {
    const std::size_t end = std::min(bytes_.find('\n', at_), bytes_.size());
    std::string text = bytes_.substr(at_, end - at_);
    at_ = std::min(end + 1, bytes_.size());
    while (!text.empty() && isSpace(text.back())) text.pop_back();
    return text;
  }
  /// The next whitespace-separated token, "" at the end of the file.
  std::string word() {
    skipSpace();
    const std::size_t start = at_;
    while (at_ < bytes_.size() && !isSpace(bytes_[at_])) ++at_;
    return bytes_.substr(start, at_ - start);
  }
  void skipSpace() {
    while (at_ < bytes_.size() && isSpace(bytes_[at_])) ++at_;
  }
  /// Moves past the current line and the following lines up to an empty one (a METADATA block).
  void skipBlock() {
    line();
    while (at_ < bytes_.size() && !line().empty()) continue;
  }
  bool startsWith(const char* text) const { return bytes_.compare(at_, std::strlen(text), text) == 0; }

  /// A count in a section header: a non-negative integer.
  long count(const std::string& section) {
    const std::string token = word();
    const auto value = parseInteger(token);
    if (!value || *value < 0) fail(section + ": '" + token + "' is not a count");
    return *value;
  }
  /// Refuses `values` values of `type` when the rest of the file cannot hold them (before any allocation).
  void expectData(long values, const std::string& type, const std::string& section) const {
    const std::size_t size = typeSize(type);
    if (size == 0) fail(section + ": data type '" + type + "' is not supported (float, double, int, vtktypeint32, vtktypeint64)");
    const std::size_t least = binary ? size : 2;  // a digit and a separator
    if (static_cast<std::size_t>(values) > (bytes_.size() - at_ + 1) / least)
      fail(section + ": " + std::to_string(values) + " values declared, more than the rest of the file holds");
  }
  double real(const std::string& type, const std::string& section) {
    if (!binary) {
      const std::string token = word();
      const auto value = parseReal(token);
      if (!value) fail(section + (token.empty() ? ": the file ends early" : ": '" + token + "' is not a number"));
      return *value;
    }
    const std::uint64_t raw = bigEndian(typeSize(type), section);
    if (type == "float") return bitCast<float>(static_cast<std::uint32_t>(raw));
    if (type == "double") return bitCast<double>(raw);
    return static_cast<double>(signedValue(raw, type));
  }
  long integer(const std::string& type, const std::string& section) {
    if (type == "float" || type == "double") fail(section + ": ids must have an integer type, not " + type);
    if (!binary) {
      const std::string token = word();
      const auto value = parseInteger(token);
      if (!value) fail(section + (token.empty() ? ": the file ends early" : ": '" + token + "' is not an integer"));
      return *value;
    }
    return signedValue(bigEndian(typeSize(type), section), type);
  }

  [[noreturn]] void fail(const std::string& problem) const {
    const std::string where = binary ? "byte " + std::to_string(at_)
                                     : "line " + std::to_string(1 + std::count(bytes_.begin(), bytes_.begin() + static_cast<long>(at_), '\n'));
    throw IoError("VTK file '" + name_ + "': " + problem + " (at " + where + ")");
  }

private:
  std::uint64_t bigEndian(std::size_t size, const std::string& section) {
    if (at_ + size > bytes_.size()) fail(section + ": the file ends early");
    std::uint64_t raw = 0;
    for (std::size_t b = 0; b < size; ++b) raw = (raw << 8) | static_cast<unsigned char>(bytes_[at_++]);
    return raw;
  }
  static long signedValue(std::uint64_t raw, const std::string& type) {
    return typeSize(type) == 4 ? static_cast<long>(static_cast<std::int32_t>(raw)) : static_cast<long>(static_cast<std::int64_t>(raw));
  }
  template <class T, class Raw>
  static double bitCast(Raw raw) {
    T value;
    std::memcpy(&value, &raw, sizeof value);
    return static_cast<double>(value);
  }

  const std::string& bytes_;
  std::string name_;
  std::size_t at_ = 0;
};

void readPoints(LegacyCursor& in, VtkCells& grid) {
  const long n = in.count("POINTS");
  const std::string type = in.word();
  in.line();
  in.expectData(n, type, "POINTS");  // first, so that 3 n cannot overflow
  in.expectData(3 * n, type, "POINTS");
  grid.points.resize(3, n);
  for (long p = 0; p < n; ++p)
    for (int k = 0; k < 3; ++k) grid.points(k, p) = in.real(type, "POINTS");
}

/// VTK 5.1: CELLS <offsets> <ids>, then OFFSETS and CONNECTIVITY arrays.
void readOffsetCells(LegacyCursor& in, VtkCells& grid, long offsetCount, long idCount) {
  in.word();  // OFFSETS
  const std::string offsetType = in.word();
  in.line();
  in.expectData(offsetCount, offsetType, "OFFSETS");
  grid.offsets.clear();
  for (long c = 0; c < offsetCount; ++c) {
    const long offset = in.integer(offsetType, "OFFSETS");
    if (offset < (c == 0 ? 0 : grid.offsets.back()) || offset > idCount || (c == 0 && offset != 0))
      in.fail("OFFSETS: offset " + std::to_string(c) + " is " + std::to_string(offset) + ", not in order within [0, " + std::to_string(idCount) + "]");
    grid.offsets.push_back(offset);
  }
  if (grid.offsets.empty() || grid.offsets.back() != idCount)
    in.fail("OFFSETS: the last offset must equal the " + std::to_string(idCount) + " ids CELLS declares");
  if (upper(in.word()) != "CONNECTIVITY") in.fail("CONNECTIVITY expected after OFFSETS");
  const std::string idType = in.word();
  in.line();
  in.expectData(idCount, idType, "CONNECTIVITY");
  grid.connectivity.resize(static_cast<std::size_t>(idCount));
  for (long& id : grid.connectivity) id = in.integer(idType, "CONNECTIVITY");
}

/// Before 5.1: CELLS <cells> <size>, each cell its point count then its ids, <size> integers in all.
void readCountedCells(LegacyCursor& in, VtkCells& grid, long cellCount, long size) {
  in.expectData(size, "int", "CELLS");
  if (cellCount > size) in.fail("CELLS: " + std::to_string(cellCount) + " cells cannot fit in " + std::to_string(size) + " values");
  grid.connectivity.reserve(static_cast<std::size_t>(size - cellCount));
  for (long c = 0, used = 0; c < cellCount; ++c) {
    const long points = in.integer("int", "CELLS");
    if (points < 0 || points > size - used - 1)
      in.fail("CELLS: cell " + std::to_string(c) + " declares " + std::to_string(points) + " points, but only " +
              std::to_string(std::max(0L, size - used - 1)) + " of the " + std::to_string(size) + " values declared remain");
    for (long k = 0; k < points; ++k) grid.connectivity.push_back(in.integer("int", "CELLS"));
    grid.offsets.push_back(static_cast<long>(grid.connectivity.size()));
    used += 1 + points;
  }
  if (static_cast<long>(grid.connectivity.size()) + cellCount != size)
    in.fail("CELLS: its cells hold " + std::to_string(grid.connectivity.size() + cellCount) + " values, not the " + std::to_string(size) + " declared");
}

void readCells(LegacyCursor& in, VtkCells& grid) {
  const long first = in.count("CELLS"), second = in.count("CELLS");
  in.line();
  if (!in.binary) in.skipSpace();
  if (in.startsWith("OFFSETS")) readOffsetCells(in, grid, first, second);
  else readCountedCells(in, grid, first, second);
}

void readTypes(LegacyCursor& in, VtkCells& grid) {
  const long n = in.count("CELL_TYPES");
  in.line();
  in.expectData(n, "int", "CELL_TYPES");
  grid.types.resize(static_cast<std::size_t>(n));
  for (int& type : grid.types) {
    const long value = in.integer("int", "CELL_TYPES");
    if (value < 0 || value > 255) in.fail("CELL_TYPES: " + std::to_string(value) + " is not a VTK cell type");
    type = static_cast<int>(value);
  }
}

}  // namespace

VtkCells readVtkLegacy(const std::string& bytes, const std::string& name) {
  LegacyCursor in(bytes, name);
  if (in.line().rfind("# vtk DataFile Version", 0) != 0) in.fail("its first line must be '# vtk DataFile Version x.y'");
  in.line();  // title
  const std::string format = upper(in.line());
  in.binary = format == "BINARY";
  if (!in.binary && format != "ASCII") in.fail("its third line must be ASCII or BINARY");
  if (upper(in.word()) != "DATASET") in.fail("DATASET expected");
  std::string dataset = upper(in.word());
  std::transform(dataset.begin(), dataset.end(), dataset.begin(), [](unsigned char c) { return std::tolower(c); });
  if (dataset != "unstructured_grid") in.fail("its dataset is " + dataset + ", not an unstructured_grid");
  in.line();
  VtkCells grid;
  bool points = false, cells = false, types = false;
  for (std::string key = upper(in.word()); !key.empty() && key != "POINT_DATA" && key != "CELL_DATA"; key = upper(in.word())) {
    if (key == "METADATA") {
      in.skipBlock();
      continue;
    }
    if (key != "POINTS" && key != "CELLS" && key != "CELL_TYPES") in.fail("has a section '" + key + "' an unstructured grid does not have here");
    bool& seen = key == "POINTS" ? points : key == "CELLS" ? cells : types;
    if (seen) in.fail("repeats " + key);
    seen = true;
    if (key == "POINTS") readPoints(in, grid);
    else if (key == "CELLS") readCells(in, grid);
    else readTypes(in, grid);
  }
  if (!points) in.fail("has no POINTS");
  if (grid.types.size() + 1 != grid.offsets.size())
    in.fail(std::to_string(grid.offsets.size() - 1) + " CELLS but " + std::to_string(grid.types.size()) + " CELL_TYPES");
  return grid;
}

}  // namespace deformation_enrichment::mesh::detail
