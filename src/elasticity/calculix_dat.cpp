#include "deformation_enrichment/elasticity/calculix_dat.hpp"

#include <optional>
#include <sstream>
#include <vector>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/number_parsing.hpp"

namespace deformation_enrichment::elasticity {
namespace {

constexpr const char* kHeader = "displacements (vx,vy,vz) for set";

// Fortran's Ew.d drops the 'E' of a three-digit exponent ("0.123456-100"); put it back before parsing.
std::optional<double> parseFortranReal(std::string token) {
  if (std::optional<double> value = parseReal(token)) return value;
  const std::size_t sign = token.find_last_of("+-");
  if (sign == std::string::npos || sign == 0 || token.find_first_of("eEdD") != std::string::npos) return std::nullopt;
  token.insert(sign, 1, 'E');
  return parseReal(token);
}

std::vector<std::string> tokens(const std::string& line) {
  std::istringstream in(line);
  std::vector<std::string> words;
  for (std::string word; in >> word;) words.push_back(word);
  return words;
}

struct Block {
  double time = 0.0;
  Eigen::Matrix3Xd values;
  std::vector<bool> seen;
  Eigen::Index count = 0;
};

}  // namespace

CalculixDisplacements readCalculixDisplacements(std::istream& in, Eigen::Index nodeCount, const std::string& source) {
  std::optional<Block> block;
  std::size_t lineNumber = 0;
  const auto fail = [&](const std::string& why) {
    throw IoError(source + ":" + std::to_string(lineNumber) + ": " + why);
  };
  for (std::string line; std::getline(in, line);) {
    ++lineNumber;
    const std::vector<std::string> words = tokens(line);
    if (words.empty()) continue;
    if (line.find(kHeader) != std::string::npos) {
      if (block && block->count != nodeCount) break;  // an earlier block is incomplete: report it below
      const std::optional<double> time = parseFortranReal(words.back());
      if (!time) fail("no step time in the displacement header");
      block = Block{*time, Eigen::Matrix3Xd::Zero(3, nodeCount), std::vector<bool>(static_cast<std::size_t>(nodeCount)), 0};
      continue;
    }
    if (!block) continue;  // other output before the first block
    const std::optional<long> node = words.size() == 4 ? parseInteger(words[0]) : std::nullopt;
    if (!node) fail("expected 'node ux uy uz', got '" + line + "'");
    if (*node < 1 || *node > nodeCount) fail("node " + std::to_string(*node) + " outside 1.." + std::to_string(nodeCount));
    const std::size_t index = static_cast<std::size_t>(*node - 1);
    if (block->seen[index]) fail("node " + std::to_string(*node) + " listed twice in one block");
    for (int axis = 0; axis < 3; ++axis) {
      const std::optional<double> value = parseFortranReal(words[static_cast<std::size_t>(axis) + 1]);
      if (!value) fail("bad displacement '" + words[static_cast<std::size_t>(axis) + 1] + "'");
      block->values(axis, static_cast<Eigen::Index>(index)) = *value;
    }
    block->seen[index] = true;
    ++block->count;
  }
  if (!block) throw IoError(source + ": no displacement block (\"" + std::string(kHeader) + " ...\")");
  if (block->count != nodeCount)
    throw IoError(source + ": a displacement block lists " + std::to_string(block->count) + " of " +
                  std::to_string(nodeCount) + " nodes");
  return {block->time, block->values};
}

}  // namespace deformation_enrichment::elasticity
