#include "deformation_enrichment/mesh/obj_reader.hpp"

#include <cmath>
#include <cstdint>
#include <istream>
#include <limits>
#include <optional>
#include <sstream>
#include <string_view>
#include <vector>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/polygon_triangulation.hpp"
#include "deformation_enrichment/number_parsing.hpp"

namespace deformation_enrichment::mesh {
namespace {

class ObjParser {
public:
  explicit ObjParser(std::string name) : name_(std::move(name)) {}

  [[noreturn]] void fail(const std::string& problem) const {
    throw IoError(name_ + ":" + std::to_string(line_) + ": " + problem);
  }

  void statement(std::istringstream& tokens) {
    ++line_;
    std::string keyword;
    if (!(tokens >> keyword)) return;
    if (keyword == "v") vertex(tokens);
    if (keyword == "f") face(tokens);
  }

  TriangleMesh mesh() const {
    TriangleMesh mesh;
    const auto count = static_cast<Eigen::Index>(positions_.size() / 3);
    if (count == 0) throw IoError(name_ + ": no vertices");
    mesh.vertices = Eigen::Map<const Eigen::Matrix3Xd>(positions_.data(), 3, count);
    try {
      mesh.triangles = fanTriangulate(faces_, count, [](const std::vector<long>& face) -> const auto& { return face; });
    } catch (const InvalidInputError& e) {
      throw IoError(name_ + ": " + e.what());
    }
    if (mesh.numTriangles() == 0) throw IoError(name_ + ": no triangles");
    return mesh;
  }

private:
  void vertex(std::istringstream& tokens) {
    std::string token;
    for (int k = 0; k < 3; ++k) {
      if (!(tokens >> token)) fail("vertex needs x y z");
      const std::optional<double> value = parseReal(token);
      if (!value) fail("vertex coordinate '" + token + "' is not a number");
      if (!std::isfinite(*value)) fail("vertex coordinate is not finite");
      positions_.push_back(*value);
    }
  }

  // Corners are 0-based after this; positive indices may refer to vertices defined further down the
  // file (fanTriangulate checks them against the final count), negative ones to those read so far.
  void face(std::istringstream& tokens) {
    std::vector<long> corners;
    for (std::string token; tokens >> token;) {
      const std::string_view index(token.data(), token.find('/') == std::string::npos ? token.size() : token.find('/'));
      const std::optional<long> value = parseInteger(index);
      if (!value || *value == 0) fail("face corner '" + token + "' has no valid vertex index");
      const long read = static_cast<long>(positions_.size() / 3);
      if (*value < -read) fail("face corner '" + token + "' counts back past the first vertex");
      if (*value > std::numeric_limits<int>::max()) fail("face corner '" + token + "' is out of range");
      corners.push_back(*value < 0 ? read + *value : *value - 1);
    }
    faces_.push_back(std::move(corners));
  }

  std::string name_;
  int line_ = 0;
  std::vector<double> positions_;
  std::vector<std::vector<long>> faces_;
};

}  // namespace

TriangleMesh readObj(std::istream& in, const std::string& name) {
  ObjParser parser(name);
  for (std::string text; std::getline(in, text);) {
    const auto hash = text.find('#');
    if (hash != std::string::npos) text.erase(hash);
    std::istringstream tokens(text);
    parser.statement(tokens);
  }
  return parser.mesh();
}

}  // namespace deformation_enrichment::mesh
