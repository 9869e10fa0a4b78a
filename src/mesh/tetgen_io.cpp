#include "deformation_enrichment/mesh/tetgen_io.hpp"

#include <array>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <vector>

#include "deformation_enrichment/error.hpp"
#include "tet_collector.hpp"

namespace deformation_enrichment::mesh {
namespace {

/// One non-blank line of a TetGen file with its 1-based line number, comment stripped.
struct Record {
  int line;
  std::vector<std::string> fields;
};

class RecordReader {
public:
  RecordReader(std::istream& in, std::string path) : path_(std::move(path)), in_(in) {}

  /// Next record; throws IoError when the file ends early (`what` says what was expected).
  Record next(const std::string& what) {
    std::string text;
    while (std::getline(in_, text)) {
      ++line_;
      const auto hash = text.find('#');
      if (hash != std::string::npos) text.erase(hash);
      std::istringstream tokens(text);
      Record record{line_, {}};
      for (std::string token; tokens >> token;) record.fields.push_back(token);
      if (!record.fields.empty()) return record;
    }
    throw IoError(path_ + ": file ends after line " + std::to_string(line_) + " but " + what + " is missing");
  }

  [[noreturn]] void fail(int line, const std::string& message) const {
    throw IoError(path_ + ":" + std::to_string(line) + ": " + message);
  }

  long integer(const Record& record, std::size_t field, const std::string& name) const {
    if (field >= record.fields.size()) fail(record.line, "missing " + name);
    const std::string& token = record.fields[field];
    std::size_t used = 0;
    long value = 0;
    try {
      value = std::stol(token, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != token.size()) fail(record.line, name + " '" + token + "' is not an integer");
    return value;
  }

  double real(const Record& record, std::size_t field, const std::string& name) const {
    if (field >= record.fields.size()) fail(record.line, "missing " + name);
    const std::string& token = record.fields[field];
    std::size_t used = 0;
    double value = 0.0;
    try {
      value = std::stod(token, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != token.size()) fail(record.line, name + " '" + token + "' is not a number");
    if (!std::isfinite(value)) fail(record.line, name + " is not finite");
    return value;
  }

private:
  std::string path_;
  std::istream& in_;
  int line_ = 0;
};

}  // namespace

TetGenMesh readTetGen(std::istream& nodeStream, std::istream& eleStream, const std::string& base) {
  TetGenMesh result;
  int indexBase = 0;
  Eigen::Matrix3Xd vertices;
  {
    RecordReader node(nodeStream, base + ".node");
    const Record header = node.next("the header");
    const long count = node.integer(header, 0, "point count");
    const long dimension = header.fields.size() > 1 ? node.integer(header, 1, "dimension") : 3;
    const long attributes = header.fields.size() > 2 ? node.integer(header, 2, "attribute count") : 0;
    const long markers = header.fields.size() > 3 ? node.integer(header, 3, "boundary-marker flag") : 0;
    if (count <= 0) node.fail(header.line, "point count must be positive, got " + std::to_string(count));
    if (dimension != 3) node.fail(header.line, "dimension must be 3, got " + std::to_string(dimension));
    if (attributes < 0 || markers < 0 || markers > 1) node.fail(header.line, "invalid attribute/marker counts");
    std::vector<Eigen::Vector3d> points;  // grows with the file: a corrupt count cannot exhaust memory
    for (long i = 0; i < count; ++i) {
      const Record record = node.next("point " + std::to_string(i));
      const long index = node.integer(record, 0, "point index");
      if (i == 0) {
        if (index != 0 && index != 1) node.fail(record.line, "first point index must be 0 or 1");
        indexBase = static_cast<int>(index);
      }
      if (index != i + indexBase)
        node.fail(record.line, "point index " + std::to_string(index) + " out of sequence (expected " +
                                   std::to_string(i + indexBase) + ")");
      if (static_cast<long>(record.fields.size()) < 4 + attributes + markers)
        node.fail(record.line, "point has " + std::to_string(record.fields.size()) + " fields, expected " +
                                   std::to_string(4 + attributes + markers));
      points.emplace_back(node.real(record, 1, "coordinate"), node.real(record, 2, "coordinate"),
                          node.real(record, 3, "coordinate"));
    }
    vertices.resize(3, count);
    for (long i = 0; i < count; ++i) vertices.col(i) = points[static_cast<size_t>(i)];
  }
  RecordReader ele(eleStream, base + ".ele");
  const Record header = ele.next("the header");
  const long count = ele.integer(header, 0, "tetrahedron count");
  const long corners = header.fields.size() > 1 ? ele.integer(header, 1, "nodes per tetrahedron") : 4;
  const long attributes = header.fields.size() > 2 ? ele.integer(header, 2, "attribute count") : 0;
  if (count <= 0) ele.fail(header.line, "tetrahedron count must be positive, got " + std::to_string(count));
  if (corners != 4 && corners != 10) ele.fail(header.line, "nodes per tetrahedron must be 4 or 10");
  if (attributes < 0) ele.fail(header.line, "negative attribute count");
  detail::TetCollector tets(base + ".ele", "line");
  const long vertexCount = vertices.cols();
  for (long t = 0; t < count; ++t) {
    const Record record = ele.next("tetrahedron " + std::to_string(t));
    const long index = ele.integer(record, 0, "tetrahedron index");
    if (index != t + indexBase)
      ele.fail(record.line, "tetrahedron index " + std::to_string(index) + " out of sequence (expected " +
                                std::to_string(t + indexBase) + ")");
    if (static_cast<long>(record.fields.size()) < 1 + corners + attributes)
      ele.fail(record.line, "tetrahedron has " + std::to_string(record.fields.size()) + " fields, expected " +
                                std::to_string(1 + corners + attributes));
    std::array<long, 4> tet{};
    for (size_t k = 0; k < 4; ++k) {
      tet[k] = ele.integer(record, 1 + k, "node index") - indexBase;
      if (tet[k] < 0 || tet[k] >= vertexCount)
        ele.fail(record.line, "node index " + record.fields[1 + k] + " out of range (" +
                                  std::to_string(vertexCount) + " points, base " + std::to_string(indexBase) + ")");
    }
    const int region =
        attributes > 0 ? static_cast<int>(std::lround(ele.real(record, 1 + corners, "region attribute"))) : 0;
    tets.add(tet, region, record.line);
  }
  std::vector<long> ids(static_cast<size_t>(vertexCount));
  for (long i = 0; i < vertexCount; ++i) ids[static_cast<size_t>(i)] = i + indexBase;
  VolumeMeshFile file = tets.finish(std::move(vertices), std::move(ids));
  result.mesh = std::move(file.mesh);
  result.region = std::move(file.region);
  result.reorientedTets = file.report.reorientedTets;
  result.unusedNodes = file.report.unusedNodes;
  result.indexBase = indexBase;
  return result;
}

TetGenMesh readTetGen(const std::string& base) {
  std::ifstream node(base + ".node");
  if (!node) throw IoError("cannot open TetGen file " + base + ".node");
  std::ifstream ele(base + ".ele");
  if (!ele) throw IoError("cannot open TetGen file " + base + ".ele");
  return readTetGen(node, ele, base);
}

void writeTetGen(const std::string& base, const TetMesh& mesh, const Eigen::VectorXi& region) {
  validate(mesh, false);
  if (region.size() != 0 && region.size() != mesh.numTets())
    throw InvalidInputError("writeTetGen: region has " + std::to_string(region.size()) + " entries for " +
                            std::to_string(mesh.numTets()) + " tets");
  {
    std::ofstream node(base + ".node");
    if (!node) throw IoError("cannot write TetGen file " + base + ".node");
    node << std::setprecision(17) << mesh.numVertices() << " 3 0 0\n";
    for (Eigen::Index v = 0; v < mesh.numVertices(); ++v)
      node << v << ' ' << mesh.vertices(0, v) << ' ' << mesh.vertices(1, v) << ' ' << mesh.vertices(2, v) << '\n';
    if (!node) throw IoError("failed while writing " + base + ".node");
  }
  std::ofstream ele(base + ".ele");
  if (!ele) throw IoError("cannot write TetGen file " + base + ".ele");
  ele << mesh.numTets() << " 4 " << (region.size() ? 1 : 0) << '\n';
  for (Eigen::Index t = 0; t < mesh.numTets(); ++t) {
    ele << t;
    for (int k = 0; k < 4; ++k) ele << ' ' << mesh.tets(k, t);
    if (region.size()) ele << ' ' << region[t];
    ele << '\n';
  }
  if (!ele) throw IoError("failed while writing " + base + ".ele");
}

}  // namespace deformation_enrichment::mesh
