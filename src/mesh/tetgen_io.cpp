#include "deformation_enrichment/mesh/tetgen_io.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <iomanip>
#include <limits>
#include <sstream>
#include <vector>

#include "deformation_enrichment/atomic_file.hpp"
#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/number_parsing.hpp"

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

  /// A record's leading index must be `expected` and it must have at least `needed` fields.
  void checkRecord(const Record& record, long index, long expected, std::uint64_t needed, const std::string& what) const {
    if (index != expected)
      fail(record.line, what + " index " + std::to_string(index) + " out of sequence (expected " +
                            std::to_string(expected) + ")");
    if (record.fields.size() < needed)
      fail(record.line, what + " has " + std::to_string(record.fields.size()) + " fields, expected " +
                            std::to_string(needed));
  }

  long integer(const Record& record, std::size_t field, const std::string& name) const {
    if (field >= record.fields.size()) fail(record.line, "missing " + name);
    const std::optional<long> value = parseInteger(record.fields[field]);
    if (!value) fail(record.line, name + " '" + record.fields[field] + "' is not an integer");
    return *value;
  }

  double real(const Record& record, std::size_t field, const std::string& name) const {
    if (field >= record.fields.size()) fail(record.line, "missing " + name);
    const std::optional<double> value = parseReal(record.fields[field]);
    if (!value) fail(record.line, name + " '" + record.fields[field] + "' is not a number");
    if (!std::isfinite(*value)) fail(record.line, name + " is not finite");
    return *value;
  }

private:
  std::string path_;
  std::istream& in_;
  int line_ = 0;
};

}  // namespace

namespace {

// Room for column `index`. Columns grow with the records actually read (doubling, up to the declared
// count), so a header that declares 10^18 points in a short file allocates nothing for them.
template <class Matrix>
void reserveColumn(Matrix& m, long index, long declared) {
  if (index < m.cols()) return;
  m.conservativeResize(Eigen::NoChange, std::min(declared, std::max(2 * static_cast<long>(m.cols()), 1024L)));
}

// Fields a record needs: `fixed` ones plus header-declared counts (up to LONG_MAX, hence unsigned).
std::uint64_t fieldsNeeded(long fixed, long declared, long more = 0) {
  return static_cast<std::uint64_t>(fixed) + static_cast<std::uint64_t>(declared) + static_cast<std::uint64_t>(more);
}

// The .node file into mesh.vertices; returns the index base (0 or 1) of the first point.
int readNodes(RecordReader& node, TetMesh& mesh) {
  const Record header = node.next("the header");
  const long count = node.integer(header, 0, "point count");
  const long dimension = header.fields.size() > 1 ? node.integer(header, 1, "dimension") : 3;
  const long attributes = header.fields.size() > 2 ? node.integer(header, 2, "attribute count") : 0;
  const long markers = header.fields.size() > 3 ? node.integer(header, 3, "boundary-marker flag") : 0;
  if (count <= 0) node.fail(header.line, "point count must be positive, got " + std::to_string(count));
  if (dimension != 3) node.fail(header.line, "dimension must be 3, got " + std::to_string(dimension));
  if (attributes < 0 || markers < 0 || markers > 1) node.fail(header.line, "invalid attribute/marker counts");
  const std::uint64_t needed = fieldsNeeded(4, attributes, markers);
  int indexBase = 0;
  for (long i = 0; i < count; ++i) {
    const Record record = node.next("point " + std::to_string(i));
    const long index = node.integer(record, 0, "point index");
    if (i == 0) {
      if (index != 0 && index != 1) node.fail(record.line, "first point index must be 0 or 1");
      indexBase = static_cast<int>(index);
    }
    node.checkRecord(record, index, i + indexBase, needed, "point");
    reserveColumn(mesh.vertices, i, count);
    for (int k = 0; k < 3; ++k) mesh.vertices(k, i) = node.real(record, 1 + k, "coordinate");
  }
  return indexBase;
}

// The corners of one .ele record as 0-based vertex indices (checked against the points read).
Eigen::Vector4i tetCorners(const RecordReader& ele, const Record& record, int indexBase, long vertexCount) {
  Eigen::Vector4i tet;
  for (int k = 0; k < 4; ++k) {
    const long index = ele.integer(record, 1 + k, "node index");
    if (index < indexBase || index - indexBase >= vertexCount)
      ele.fail(record.line, "node index " + record.fields[1 + k] + " out of range (" + std::to_string(vertexCount) +
                                " points, base " + std::to_string(indexBase) + ")");
    tet[k] = static_cast<int>(index - indexBase);
    for (int j = 0; j < k; ++j)
      if (tet[j] == tet[k]) ele.fail(record.line, "repeated node index " + record.fields[1 + k]);
  }
  return tet;
}

// The .ele file into result.mesh.tets and result.region, negative tets reoriented.
void readElements(RecordReader& ele, int indexBase, TetGenMesh& result) {
  const Record header = ele.next("the header");
  const long count = ele.integer(header, 0, "tetrahedron count");
  const long corners = header.fields.size() > 1 ? ele.integer(header, 1, "nodes per tetrahedron") : 4;
  const long attributes = header.fields.size() > 2 ? ele.integer(header, 2, "attribute count") : 0;
  if (count <= 0) ele.fail(header.line, "tetrahedron count must be positive, got " + std::to_string(count));
  if (corners != 4 && corners != 10) ele.fail(header.line, "nodes per tetrahedron must be 4 or 10");
  if (attributes < 0) ele.fail(header.line, "negative attribute count");
  const std::uint64_t needed = fieldsNeeded(1, corners, attributes);
  std::vector<int> region;
  for (long t = 0; t < count; ++t) {
    const Record record = ele.next("tetrahedron " + std::to_string(t));
    const long index = ele.integer(record, 0, "tetrahedron index");
    ele.checkRecord(record, index, t + indexBase, needed, "tetrahedron");
    reserveColumn(result.mesh.tets, t, count);
    result.mesh.tets.col(t) = tetCorners(ele, record, indexBase, result.mesh.numVertices());
    const double id = attributes > 0 ? ele.real(record, 1 + corners, "region attribute") : 0.0;
    if (!(std::abs(id) <= std::numeric_limits<int>::max()))
      ele.fail(record.line, "region attribute " + record.fields[1 + corners] + " is outside the int range");
    region.push_back(static_cast<int>(std::lround(id)));
    double volume = signedVolume(result.mesh, t);
    if (!std::isfinite(volume)) ele.fail(record.line, "tetrahedron volume is not finite (coordinates too large)");
    if (volume < 0.0) {
      std::swap(result.mesh.tets(2, t), result.mesh.tets(3, t));
      ++result.reorientedTets;
      // Rounding can make the flipped determinant zero or negative too (badly scaled coordinates): then
      // the orientation is not determinable and the tet counts as flat.
      volume = signedVolume(result.mesh, t);
    }
    if (!(volume > 0.0)) ele.fail(record.line, "tetrahedron has zero volume");
  }
  result.region = Eigen::Map<const Eigen::VectorXi>(region.data(), static_cast<Eigen::Index>(region.size()));
}

}  // namespace

TetGenMesh readTetGen(std::istream& node, std::istream& ele, const std::string& base) {
  TetGenMesh result;
  RecordReader nodes(node, base + ".node");
  const int indexBase = readNodes(nodes, result.mesh);
  RecordReader elements(ele, base + ".ele");
  readElements(elements, indexBase, result);
  result.indexBase = indexBase;
  std::vector<char> used(static_cast<std::size_t>(result.mesh.numVertices()), 0);
  for (Eigen::Index t = 0; t < result.mesh.numTets(); ++t)
    for (int k = 0; k < 4; ++k) used[static_cast<std::size_t>(result.mesh.tets(k, t))] = 1;
  result.unusedNodes = std::count(used.begin(), used.end(), 0);
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
  std::ostringstream node, ele;
  node << std::setprecision(17) << mesh.numVertices() << " 3 0 0\n";
  for (Eigen::Index v = 0; v < mesh.numVertices(); ++v)
    node << v << ' ' << mesh.vertices(0, v) << ' ' << mesh.vertices(1, v) << ' ' << mesh.vertices(2, v) << '\n';
  ele << mesh.numTets() << " 4 " << (region.size() ? 1 : 0) << '\n';
  for (Eigen::Index t = 0; t < mesh.numTets(); ++t) {
    ele << t;
    for (int k = 0; k < 4; ++k) ele << ' ' << mesh.tets(k, t);
    if (region.size()) ele << ' ' << region[t];
    ele << '\n';
  }
  writeFileAtomically(base + ".node", node.str());
  writeFileAtomically(base + ".ele", ele.str());
}

}  // namespace deformation_enrichment::mesh
