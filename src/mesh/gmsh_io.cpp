#include "deformation_enrichment/mesh/gmsh_io.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <map>
#include <unordered_map>
#include <vector>

#include "deformation_enrichment/error.hpp"
#include "tet_collector.hpp"

namespace deformation_enrichment::mesh {
namespace {

struct ElementType {
  int type, nodes;
  const char* family;
};

// gmsh's element types up to fifth order ([gmsh], "MSH file format": element types); the four
// corners of every tetrahedron come first.
constexpr ElementType kElementTypes[] = {
    {1, 2, "line"},         {2, 3, "triangle"},      {3, 4, "quadrangle"},   {4, 4, "tetrahedron"},
    {5, 8, "hexahedron"},   {6, 6, "prism"},         {7, 5, "pyramid"},      {8, 3, "line"},
    {9, 6, "triangle"},     {10, 9, "quadrangle"},   {11, 10, "tetrahedron"}, {12, 27, "hexahedron"},
    {13, 18, "prism"},      {14, 14, "pyramid"},     {15, 1, "point"},       {16, 8, "quadrangle"},
    {17, 20, "hexahedron"}, {18, 15, "prism"},       {19, 13, "pyramid"},    {20, 9, "triangle"},
    {21, 10, "triangle"},   {22, 12, "triangle"},    {23, 15, "triangle"},   {24, 15, "triangle"},
    {25, 21, "triangle"},   {26, 4, "line"},         {27, 5, "line"},        {28, 6, "line"},
    {29, 20, "tetrahedron"}, {30, 35, "tetrahedron"}, {31, 56, "tetrahedron"}, {92, 64, "hexahedron"},
    {93, 125, "hexahedron"}};

const ElementType* elementType(long type) {
  for (const ElementType& known : kElementTypes)
    if (known.type == type) return &known;
  return nullptr;
}

/// The bytes of a .msh file with a read position: whitespace-separated ASCII tokens (counting lines)
/// and raw little-endian binary values.
class MshInput {
public:
  MshInput(std::string bytes, std::string name) : bytes_(std::move(bytes)), name_(std::move(name)) {}

  bool binary = false;  ///< whether errors name byte offsets (binary data) rather than lines

  const std::string& name() const { return name_; }
  int line() const { return line_; }

  bool atEnd() {
    skipSpace();
    return pos_ == bytes_.size();
  }

  std::string word(const char* what) {
    if (atEnd()) fail("file ends where " + std::string(what) + " should be");
    const size_t start = pos_;
    while (pos_ < bytes_.size() && !std::isspace(static_cast<unsigned char>(bytes_[pos_]))) ++pos_;
    return bytes_.substr(start, pos_ - start);
  }

  void expect(const std::string& token) {
    const std::string found = word(token.c_str());
    if (found != token) fail("expected " + token + ", found '" + found.substr(0, 40) + "'");
  }

  long integer(const char* what) {
    const std::string token = word(what);
    char* end = nullptr;
    errno = 0;
    const long value = std::strtol(token.c_str(), &end, 10);
    if (token.empty() || *end != '\0' || errno == ERANGE)
      fail(std::string(what) + " '" + token.substr(0, 40) + "' is not an integer");
    return value;
  }

  double real(const char* what) {
    const std::string token = word(what);
    char* end = nullptr;
    const double value = std::strtod(token.c_str(), &end);
    if (token.empty() || *end != '\0') fail(std::string(what) + " '" + token.substr(0, 40) + "' is not a number");
    if (!std::isfinite(value)) fail(std::string(what) + " is not finite");
    return value;
  }

  template <class T>
  T raw(const char* what) {
    if (bytes_.size() - pos_ < sizeof(T)) fail("file ends inside " + std::string(what));
    T value;
    std::memcpy(&value, bytes_.data() + pos_, sizeof(T));
    pos_ += sizeof(T);
    return value;
  }

  /// The single newline between an ASCII header and binary data.
  void newline() {
    if (pos_ >= bytes_.size() || bytes_[pos_] != '\n') fail("expected a line break before binary data");
    ++pos_;
    ++line_;
  }

  /// Moves past "$End<name>".
  void skipSection(const std::string& name) {
    const std::string end = "$End" + name;
    const size_t found = bytes_.find(end, pos_);
    if (found == std::string::npos) fail("section $" + name + " has no " + end);
    line_ += static_cast<int>(std::count(bytes_.begin() + static_cast<std::ptrdiff_t>(pos_),
                                         bytes_.begin() + static_cast<std::ptrdiff_t>(found), '\n'));
    pos_ = found + end.size();
  }

  [[noreturn]] void fail(const std::string& message) const {
    if (binary) throw IoError(name_ + ": byte " + std::to_string(pos_) + ": " + message);
    throw IoError(name_ + ":" + std::to_string(line_) + ": " + message);
  }

private:
  void skipSpace() {
    while (pos_ < bytes_.size() && std::isspace(static_cast<unsigned char>(bytes_[pos_]))) {
      if (bytes_[pos_] == '\n') ++line_;
      ++pos_;
    }
  }

  std::string bytes_, name_;
  size_t pos_ = 0;
  int line_ = 1;
};

/// A tet as read: its corners' node tags, resolved once every node is known.
struct PendingTet {
  std::array<long, 4> tags;
  int region;
  long location;
};

class MshReader {
public:
  explicit MshReader(MshInput& in) : in_(in) {}

  VolumeMeshFile read() {
    const std::string first = in_.word("$MeshFormat or $NOD");
    if (first == "$NOD") return readVersion1();
    if (first != "$MeshFormat") in_.fail("expected $MeshFormat (or $NOD of MSH 1.0), found '" + first.substr(0, 40) + "'");
    readFormat();
    bool nodes = false, elements = false;
    while (!in_.atEnd()) {
      in_.binary = false;
      const std::string section = in_.word("a section");
      if (section == "$Nodes" || section == "$Elements") {
        bool& seen = section == "$Nodes" ? nodes : elements;
        if (seen) in_.fail("second " + section + " section");
        seen = true;
        if (section == "$Nodes") version4_ ? readNodes4() : readNodes2();
        else version4_ ? readElements4() : readElements2();
        in_.binary = false;
        in_.expect("$End" + section.substr(1));
      } else if (section == "$Entities" && version4_) {
        readEntities4();
        in_.binary = false;
        in_.expect("$EndEntities");
      } else if (section.size() > 1 && section[0] == '$') {
        in_.skipSection(section.substr(1));
      } else {
        in_.fail("expected a section ($Name), found '" + section.substr(0, 40) + "'");
      }
    }
    if (!nodes || !elements) throw IoError(in_.name() + " has no " + (nodes ? "$Elements" : "$Nodes") + " section");
    return resolve();
  }

private:
  /// MSH 1.0 (SOFA's meshes, e.g. liver.msh): $NOD (tag x y z per node) and $ELM (tag, type, physical and
  /// elementary region, node count, node tags per element), ASCII only [gmsh].
  VolumeMeshFile readVersion1() {
    const long nodes = in_.integer("node count");
    for (long i = 0; i < nodes; ++i) {
      addNode(in_.integer("node tag"));
      for (int k = 0; k < 3; ++k) positions_.push_back(in_.real("coordinate"));
    }
    in_.expect("$ENDNOD");
    in_.expect("$ELM");
    const long elements = in_.integer("element count");
    for (long e = 0; e < elements; ++e) {
      in_.integer("element tag");
      const long location = in_.line();
      const ElementType* known = knownType(in_.integer("element type"));
      const int region = static_cast<int>(in_.integer("physical region"));
      in_.integer("elementary region");
      if (in_.integer("node count") != known->nodes) in_.fail("node count does not match the element type");
      element(*known, region, location, [&] { return in_.integer("node tag"); });
    }
    in_.expect("$ENDELM");
    if (!in_.atEnd()) in_.fail("content after $ENDELM");
    return resolve();
  }

  void readFormat() {
    const std::string version = in_.word("the format version");
    if (version == "4.1") version4_ = true;
    else if (version.rfind("2.", 0) != 0)
      in_.fail("MSH version " + version.substr(0, 20) + " is not supported (save as 2.2 or 4.1)");
    const long fileType = in_.integer("file type");
    const long dataSize = in_.integer("data size");
    if (fileType != 0 && fileType != 1) in_.fail("file type must be 0 (ASCII) or 1 (binary)");
    if (dataSize != 8) in_.fail("data size must be 8 (double precision), got " + std::to_string(dataSize));
    binaryFile_ = fileType == 1;
    if (binaryFile_) {
      in_.newline();
      in_.binary = true;
      if (in_.raw<std::int32_t>("the byte-order mark") != 1) in_.fail("binary data is not little-endian");
      in_.binary = false;
    }
    in_.expect("$EndMeshFormat");
  }

  /// A count or tag of version 4.1: size_t or int in binary files, text in ASCII ones.
  long value(bool sizeT, const char* what) {
    if (!binaryFile_) return in_.integer(what);
    const long v = sizeT ? static_cast<long>(in_.raw<std::uint64_t>(what)) : in_.raw<std::int32_t>(what);
    if (sizeT && v < 0) in_.fail(std::string(what) + " is too large");
    return v;
  }
  double coordinate() { return binaryFile_ ? in_.raw<double>("a coordinate") : in_.real("coordinate"); }

  /// Binary section data starts after the line break that ends the section's ASCII header.
  void enterData() {
    if (!binaryFile_) return;
    in_.newline();
    in_.binary = true;
  }

  void addNode(long tag) {
    if (!index_.emplace(tag, static_cast<long>(ids_.size())).second)
      in_.fail("node tag " + std::to_string(tag) + " appears twice");
    ids_.push_back(tag);
  }

  void readNodes2() {
    const long count = in_.integer("node count");
    enterData();
    for (long i = 0; i < count; ++i) {
      addNode(binaryFile_ ? in_.raw<std::int32_t>("a node tag") : in_.integer("node tag"));
      for (int k = 0; k < 3; ++k) positions_.push_back(coordinate());
    }
  }

  void readElements2() {
    const long count = in_.integer("element count");
    enterData();
    for (long read = 0; read < count;) {
      // Binary elements come in blocks of one type sharing a header; ASCII ones have their own.
      long type = 0, following = 1, tagCount = 0;
      if (binaryFile_) {
        type = in_.raw<std::int32_t>("an element header");
        following = in_.raw<std::int32_t>("an element header");
        tagCount = in_.raw<std::int32_t>("an element header");
        if (following <= 0 || following > count - read || tagCount < 0) in_.fail("invalid element block header");
      }
      for (long e = 0; e < following; ++e, ++read) {
        const long tag = binaryFile_ ? in_.raw<std::int32_t>("an element tag") : in_.integer("element tag");
        const long location = in_.line();
        if (!binaryFile_) {
          type = in_.integer("element type");
          tagCount = in_.integer("tag count");
          if (tagCount < 0) in_.fail("negative tag count");
        }
        const ElementType* known = knownType(type);
        int region = 0;
        for (long k = 0; k < tagCount; ++k) {
          const long t = binaryFile_ ? in_.raw<std::int32_t>("an element tag") : in_.integer("element tag");
          if (k == 0) region = static_cast<int>(t);  // the physical entity
        }
        element(*known, region, binaryFile_ ? tag : location, [&] {
          return binaryFile_ ? in_.raw<std::int32_t>("a node tag") : in_.integer("node tag");
        });
      }
    }
  }

  void readEntities4() {
    enterData();
    long counts[4];
    for (long& c : counts) c = value(true, "entity count");
    for (int dim = 0; dim < 4; ++dim) {
      for (long e = 0; e < counts[dim]; ++e) {
        const long tag = value(false, "entity tag");
        for (int k = 0; k < (dim == 0 ? 3 : 6); ++k) coordinate();
        const long physicals = value(true, "physical tag count");
        for (long p = 0; p < physicals; ++p) {
          const long physical = value(false, "physical tag");
          if (dim == 3 && p == 0) volumePhysical_[tag] = static_cast<int>(physical);
        }
        if (dim == 0) continue;
        const long bounding = value(true, "bounding entity count");
        for (long b = 0; b < bounding; ++b) value(false, "bounding entity tag");
      }
    }
  }

  void readNodes4() {
    enterData();
    const long blocks = value(true, "node block count");
    for (int k = 0; k < 3; ++k) value(true, "node count or tag range");
    for (long b = 0; b < blocks; ++b) {
      const long dim = value(false, "entity dimension");
      value(false, "entity tag");
      const long parametric = value(false, "parametric flag");
      const long count = value(true, "node count");
      if (dim < 0 || dim > 3 || (parametric != 0 && parametric != 1)) in_.fail("invalid node block header");
      for (long i = 0; i < count; ++i) addNode(value(true, "node tag"));
      for (long i = 0; i < count; ++i) {
        for (int k = 0; k < 3; ++k) positions_.push_back(coordinate());
        for (long k = 0; k < parametric * dim; ++k) coordinate();  // parametric coordinates: not needed
      }
    }
  }

  void readElements4() {
    enterData();
    const long blocks = value(true, "element block count");
    for (int k = 0; k < 3; ++k) value(true, "element count or tag range");
    for (long b = 0; b < blocks; ++b) {
      const long dim = value(false, "entity dimension");
      const long entity = value(false, "entity tag");
      const ElementType* known = knownType(value(false, "element type"));
      const long count = value(true, "element count");
      const auto physical = volumePhysical_.find(entity);
      const int region = dim == 3 && physical != volumePhysical_.end() ? physical->second : 0;
      for (long e = 0; e < count; ++e) {
        const long tag = value(true, "element tag");
        const long location = in_.line();
        element(*known, region, binaryFile_ ? tag : location, [&] { return value(true, "node tag"); });
      }
    }
  }

  const ElementType* knownType(long type) {
    const ElementType* known = elementType(type);
    if (!known) in_.fail("element type " + std::to_string(type) + " is not a gmsh element type this reader knows");
    return known;
  }

  /// Reads an element's node tags with `nextTag`; keeps a tet's corners, counts anything else.
  template <class NextTag>
  void element(const ElementType& type, int region, long location, NextTag nextTag) {
    const bool tet = std::strcmp(type.family, "tetrahedron") == 0;
    PendingTet pending{{}, region, location};
    for (int k = 0; k < type.nodes; ++k) {
      const long tag = nextTag();
      if (tet && k < 4) pending.tags[static_cast<size_t>(k)] = tag;
    }
    if (tet) tets_.push_back(pending);
    else ++skipped_[type.family];
  }

  VolumeMeshFile resolve() {
    detail::TetCollector collector(in_.name(), binaryFile_ ? "element" : "line");
    for (const auto& [family, count] : skipped_) collector.skip(family, count);
    for (const PendingTet& tet : tets_) {
      std::array<long, 4> corners{};
      for (size_t k = 0; k < 4; ++k) {
        const auto found = index_.find(tet.tags[k]);
        if (found == index_.end())
          collector.fail(tet.location, "node tag " + std::to_string(tet.tags[k]) + " is not in $Nodes");
        corners[k] = found->second;
      }
      collector.add(corners, tet.region, tet.location);
    }
    const Eigen::Index nodes = static_cast<Eigen::Index>(ids_.size());
    return collector.finish(Eigen::Map<const Eigen::Matrix3Xd>(positions_.data(), 3, nodes), std::move(ids_));
  }

  MshInput& in_;
  bool version4_ = false, binaryFile_ = false;
  std::unordered_map<long, long> index_;  // node tag -> position in the file
  std::vector<long> ids_;
  std::vector<double> positions_;
  std::unordered_map<long, int> volumePhysical_;
  std::vector<PendingTet> tets_;
  std::map<std::string, long> skipped_;
};

}  // namespace

VolumeMeshFile readGmsh(std::istream& in, const std::string& name) {
  std::string bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  if (in.bad()) throw IoError("gmsh file '" + name + "' cannot be read");
  MshInput input(std::move(bytes), name);
  return MshReader(input).read();
}

VolumeMeshFile readGmsh(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) throw IoError("cannot open gmsh file " + path);
  return readGmsh(file, path);
}

}  // namespace deformation_enrichment::mesh
