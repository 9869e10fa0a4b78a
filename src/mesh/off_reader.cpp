#include "deformation_enrichment/mesh/off_reader.hpp"

#include <cmath>
#include <istream>
#include <optional>
#include <sstream>
#include <vector>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/polygon_triangulation.hpp"
#include "deformation_enrichment/number_parsing.hpp"

namespace deformation_enrichment::mesh {
namespace {

/// The file's non-empty lines without comments, numbered for messages.
class OffLines {
public:
  OffLines(std::istream& in, std::string name) : in_(in), name_(std::move(name)) {}

  /// The tokens of the next line holding any; fails at the end of the file, naming what was expected.
  std::istringstream next(const std::string& expected) {
    std::string text;
    while (std::getline(in_, text)) {
      ++line_;
      text = text.substr(0, text.find('#'));
      if (text.find_first_not_of(" \t\r") != std::string::npos) return std::istringstream(text);
    }
    if (in_.bad()) throw IoError("OFF file '" + name_ + "' cannot be read");
    fail("the file ends before " + expected);
  }

  [[noreturn]] void fail(const std::string& problem) const {
    throw IoError("OFF file '" + name_ + "', line " + std::to_string(line_) + ": " + problem);
  }

  /// The next token of `tokens` as a non-negative integer below `bound`.
  long index(std::istringstream& tokens, long bound, const std::string& what) const {
    std::string token;
    if (!(tokens >> token)) fail(what + " is missing");
    const std::optional<long> value = parseInteger(token);
    if (!value || *value < 0 || *value >= bound) fail(what + " '" + token + "' is not an integer in [0, " + std::to_string(bound) + ")");
    return *value;
  }
  double real(std::istringstream& tokens, const std::string& what) const {
    std::string token;
    if (!(tokens >> token)) fail(what + " is missing");
    const std::optional<double> value = parseReal(token);
    if (!value || !std::isfinite(*value)) fail(what + " '" + token + "' is not a finite number");
    return *value;
  }

private:
  std::istream& in_;
  std::string name_;
  long line_ = 0;
};

/// Whether the OFF keyword's prefixes say each vertex has a homogeneous w.
bool readKeyword(const std::string& keyword, OffLines& lines, const std::string& name) {
  const auto off = keyword.rfind("OFF");
  if (off == std::string::npos || off + 3 != keyword.size()) lines.fail("the file must start with OFF, not '" + keyword + "'");
  const std::string prefixes = keyword.substr(0, off);
  if (prefixes.find('n') != std::string::npos) throw IoError("OFF file '" + name + "': nOFF (a dimension other than 3) is not supported");
  if (prefixes.find_first_not_of("STCN4") != std::string::npos) lines.fail("unknown OFF variant '" + keyword + "'");
  return prefixes.find('4') != std::string::npos;
}

}  // namespace

TriangleMesh readOff(std::istream& in, const std::string& name) {
  OffLines lines(in, name);
  std::istringstream header = lines.next("the OFF keyword");
  std::string keyword, word;
  header >> keyword;
  const bool homogeneous = readKeyword(keyword, lines, name);
  std::streampos counts = header.tellg();
  if (header >> word && word == "BINARY") throw IoError("OFF file '" + name + "': binary OFF is not supported (convert the file to ASCII OFF)");
  header.clear();
  header.seekg(counts);
  if (!(header >> std::ws) || header.eof()) header = lines.next("the vertex and face counts");
  constexpr long kMostCount = 1L << 40;  // an upper bound that keeps the arithmetic below in range
  const long vertexCount = lines.index(header, kMostCount, "vertex count");
  const long faceCount = lines.index(header, kMostCount, "face count");
  std::vector<double> positions;
  for (long v = 0; v < vertexCount; ++v) {
    std::istringstream tokens = lines.next("vertex " + std::to_string(v));
    double p[4] = {0.0, 0.0, 0.0, 1.0};
    for (int k = 0; k < (homogeneous ? 4 : 3); ++k) p[k] = lines.real(tokens, "vertex coordinate");
    if (p[3] == 0.0) lines.fail("vertex " + std::to_string(v) + " has w = 0");
    for (int k = 0; k < 3; ++k) positions.push_back(p[k] / p[3]);
  }
  std::vector<std::vector<long>> faces;
  for (long f = 0; f < faceCount; ++f) {
    std::istringstream tokens = lines.next("face " + std::to_string(f));
    const long corners = lines.index(tokens, vertexCount + 1, "corner count");  // a face repeats no vertex
    std::vector<long>& face = faces.emplace_back();
    for (long k = 0; k < corners; ++k) face.push_back(lines.index(tokens, vertexCount, "vertex index"));
  }
  TriangleMesh mesh;
  mesh.vertices = Eigen::Map<const Eigen::Matrix3Xd>(positions.data(), 3, static_cast<Eigen::Index>(vertexCount));
  for (Eigen::Index v = 0; v < mesh.numVertices(); ++v)
    if (!mesh.vertices.col(v).allFinite()) throw IoError("OFF file '" + name + "': vertex " + std::to_string(v) + " is not finite after dividing by w");
  try {
    mesh.triangles = fanTriangulate(faces, mesh.numVertices(), [](const std::vector<long>& face) -> const auto& { return face; });
  } catch (const InvalidInputError& e) {
    throw IoError("OFF file '" + name + "': " + e.what());
  }
  if (mesh.numTriangles() == 0) throw IoError("OFF file '" + name + "': no triangles");
  return mesh;
}

}  // namespace deformation_enrichment::mesh
