#include "deformation_enrichment/mesh/ply_reader.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <istream>
#include <optional>
#include <sstream>
#include <vector>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/polygon_triangulation.hpp"
#include "deformation_enrichment/number_parsing.hpp"

namespace deformation_enrichment::mesh {
namespace {

enum class Format { Ascii, BinaryLittleEndian, BinaryBigEndian };
enum class Type { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

struct TypeInfo {
  const char* name;
  const char* alias;
  Type type;
  std::size_t size;
  double lowest, highest;  // integer types: the range an ASCII value must lie in
};

constexpr TypeInfo kTypes[] = {
    {"char", "int8", Type::Int8, 1, -128.0, 127.0},
    {"uchar", "uint8", Type::UInt8, 1, 0.0, 255.0},
    {"short", "int16", Type::Int16, 2, -32768.0, 32767.0},
    {"ushort", "uint16", Type::UInt16, 2, 0.0, 65535.0},
    {"int", "int32", Type::Int32, 4, -2147483648.0, 2147483647.0},
    {"uint", "uint32", Type::UInt32, 4, 0.0, 4294967295.0},
    {"float", "float32", Type::Float32, 4, 0.0, 0.0},
    {"double", "float64", Type::Float64, 8, 0.0, 0.0},
};

const TypeInfo& info(Type type) { return kTypes[static_cast<int>(type)]; }
bool isInteger(Type type) { return type != Type::Float32 && type != Type::Float64; }

struct Property {
  std::string name;
  Type type = Type::Float32;  // of the value, or of a list's items
  std::optional<Type> countType;  // set for a list
};

struct Element {
  std::string name;
  long count = 0;
  std::vector<Property> properties;
};

struct Header {
  Format format = Format::Ascii;
  std::vector<Element> elements;
};

class HeaderParser {
public:
  explicit HeaderParser(const std::string& name) : name_(name) {}

  Header parse(std::istream& in) {
    std::string text;
    if (!nextLine(in, text) || text != "ply") fail("does not start with the line 'ply'");
    bool haveFormat = false;
    while (nextLine(in, text)) {
      std::istringstream tokens(text);
      std::string keyword;
      tokens >> keyword;
      if (keyword == "end_header") {
        if (!haveFormat) fail("no format line");
        checkLastElement();
        return header_;
      }
      if (keyword == "format") {
        format(tokens);
        haveFormat = true;
      } else if (keyword == "element") {
        element(tokens);
      } else if (keyword == "property") {
        property(tokens);
      } else if (keyword != "comment" && keyword != "obj_info") {
        fail("unknown header line '" + text + "'");
      }
    }
    throw IoError(name_ + ": file ends inside the header (no end_header)");
  }

private:
  [[noreturn]] void fail(const std::string& problem) const {
    throw IoError(name_ + ":" + std::to_string(line_) + ": " + problem);
  }

  bool nextLine(std::istream& in, std::string& text) {
    if (!std::getline(in, text)) return false;
    ++line_;
    if (!text.empty() && text.back() == '\r') text.pop_back();
    return true;
  }

  void format(std::istringstream& tokens) {
    std::string kind, version, extra;
    tokens >> kind >> version;
    if (version != "1.0" || tokens >> extra) fail("format line is not '<format> 1.0'");
    if (kind == "ascii") header_.format = Format::Ascii;
    else if (kind == "binary_little_endian") header_.format = Format::BinaryLittleEndian;
    else if (kind == "binary_big_endian") header_.format = Format::BinaryBigEndian;
    else fail("unknown format '" + kind + "'");
  }

  void element(std::istringstream& tokens) {
    Element e;
    std::string count, extra;
    if (!(tokens >> e.name >> count) || tokens >> extra) fail("element line is not 'element <name> <count>'");
    const std::optional<long> value = parseInteger(count);
    if (!value || *value < 0) fail("element count '" + count + "' is not a non-negative integer");
    for (const Element& other : header_.elements)
      if (other.name == e.name) fail("element '" + e.name + "' declared twice");
    e.count = *value;
    checkLastElement();
    header_.elements.push_back(e);
  }

  void property(std::istringstream& tokens) {
    if (header_.elements.empty()) fail("property before any element");
    Property p;
    std::string first, extra;
    tokens >> first;
    if (first == "list") {
      std::string countType, itemType;
      tokens >> countType >> itemType;
      p.countType = type(countType);
      p.type = type(itemType);
      if (!isInteger(*p.countType)) fail("list count type '" + countType + "' is not an integer type");
    } else {
      p.type = type(first);
    }
    if (!(tokens >> p.name) || tokens >> extra) fail("property line is not 'property [list <type>] <type> <name>'");
    std::vector<Property>& properties = header_.elements.back().properties;
    for (const Property& other : properties)
      if (other.name == p.name) fail("property '" + p.name + "' declared twice");
    properties.push_back(p);
  }

  Type type(const std::string& token) const {
    for (const TypeInfo& t : kTypes)
      if (token == t.name || token == t.alias) return t.type;
    fail("unknown property type '" + token + "'");
  }

  // Every instance must consume input, or a count of 10^18 would spin without reading anything.
  void checkLastElement() const {
    if (!header_.elements.empty() && header_.elements.back().count > 0 && header_.elements.back().properties.empty())
      fail("element '" + header_.elements.back().name + "' has instances but no properties");
  }

  const std::string& name_;
  int line_ = 0;
  Header header_;
};

// One value at a time from the body, ASCII tokens or binary bytes.
class ValueReader {
public:
  ValueReader(std::istream& in, Format format, const std::string& name) : in_(in), format_(format), name_(name) {}

  double value(Type type, const std::string& where) {
    if (format_ == Format::Ascii) return asciiValue(type, where);
    unsigned char bytes[8];
    const std::size_t size = info(type).size;
    if (!in_.read(reinterpret_cast<char*>(bytes), static_cast<std::streamsize>(size)))
      throw IoError(name_ + ": data ends inside " + where);
    if (format_ == Format::BinaryBigEndian) std::reverse(bytes, bytes + size);
    return decode(type, bytes);
  }

private:
  double asciiValue(Type type, const std::string& where) {
    std::string token;
    if (!(in_ >> token)) throw IoError(name_ + ": data ends inside " + where);
    if (!isInteger(type)) {
      const std::optional<double> real = parseReal(token);
      if (!real) throw IoError(name_ + ": " + where + ": '" + token + "' is not a number");
      return *real;
    }
    const std::optional<long> integer = parseInteger(token);
    if (!integer || *integer < info(type).lowest || *integer > info(type).highest)
      throw IoError(name_ + ": " + where + ": '" + token + "' is not a " + info(type).name);
    return static_cast<double>(*integer);
  }

  template <class T>
  static double as(const unsigned char* bytes) {
    T value;
    std::memcpy(&value, bytes, sizeof value);
    return static_cast<double>(value);
  }

  static double decode(Type type, const unsigned char* bytes) {
    switch (type) {
      case Type::Int8: return as<std::int8_t>(bytes);
      case Type::UInt8: return as<std::uint8_t>(bytes);
      case Type::Int16: return as<std::int16_t>(bytes);
      case Type::UInt16: return as<std::uint16_t>(bytes);
      case Type::Int32: return as<std::int32_t>(bytes);
      case Type::UInt32: return as<std::uint32_t>(bytes);
      case Type::Float32: return as<float>(bytes);
      case Type::Float64: return as<double>(bytes);
    }
    return 0.0;
  }

  std::istream& in_;
  Format format_;
  const std::string& name_;
};

// What the mesh needs from the body.
struct Geometry {
  std::vector<double> positions;  // x y z per vertex
  std::vector<std::vector<long>> faces;
};

long propertyIndex(const Element& element, std::initializer_list<const char*> names) {
  for (std::size_t p = 0; p < element.properties.size(); ++p)
    for (const char* name : names)
      if (element.properties[p].name == name) return static_cast<long>(p);
  return -1;
}

// Reads every instance of `element`; vertex x/y/z and face index lists go to `geometry`.
void readElement(ValueReader& values, const Element& element, const std::string& name, Geometry& geometry) {
  const bool isVertex = element.name == "vertex", isFace = element.name == "face";
  const long axes[3] = {propertyIndex(element, {"x"}), propertyIndex(element, {"y"}), propertyIndex(element, {"z"})};
  const long indices = propertyIndex(element, {"vertex_indices", "vertex_index"});
  for (int k = 0; isVertex && k < 3; ++k)
    if (axes[k] < 0 || element.properties[static_cast<std::size_t>(axes[k])].countType)
      throw IoError(name + ": vertex element has no scalar property '" + std::string(1, char('x' + k)) + "'");
  if (isFace && (indices < 0 || !element.properties[static_cast<std::size_t>(indices)].countType ||
                 !isInteger(element.properties[static_cast<std::size_t>(indices)].type)))
    throw IoError(name + ": face element has no integer vertex_indices list");
  for (long i = 0; i < element.count; ++i) {
    const std::string where = "element '" + element.name + "' " + std::to_string(i);
    double xyz[3] = {0.0, 0.0, 0.0};
    for (std::size_t p = 0; p < element.properties.size(); ++p) {
      const Property& property = element.properties[p];
      if (!property.countType) {
        const double value = values.value(property.type, where);
        for (int k = 0; k < 3; ++k)
          if (static_cast<long>(p) == axes[k]) xyz[k] = value;
        continue;
      }
      const double length = values.value(*property.countType, where);
      if (length < 0) throw IoError(name + ": " + where + " has a negative list length");
      const bool keep = isFace && static_cast<long>(p) == indices;  // an integer list: its values fit a long
      std::vector<long> list;
      for (auto item = static_cast<std::uint64_t>(length); item > 0; --item) {
        const double value = values.value(property.type, where);
        if (keep) list.push_back(static_cast<long>(value));
      }
      if (keep) geometry.faces.push_back(std::move(list));
    }
    if (!isVertex) continue;
    if (!std::isfinite(xyz[0]) || !std::isfinite(xyz[1]) || !std::isfinite(xyz[2]))
      throw IoError(name + ": vertex " + std::to_string(i) + " is not finite");
    geometry.positions.insert(geometry.positions.end(), xyz, xyz + 3);
  }
}

}  // namespace

TriangleMesh readPly(std::istream& in, const std::string& name) {
  const Header header = HeaderParser(name).parse(in);
  if (std::none_of(header.elements.begin(), header.elements.end(), [](const Element& e) { return e.name == "vertex"; }))
    throw IoError(name + ": no vertex element");
  ValueReader values(in, header.format, name);
  Geometry geometry;
  for (const Element& element : header.elements) readElement(values, element, name, geometry);
  TriangleMesh mesh;
  const auto count = static_cast<Eigen::Index>(geometry.positions.size() / 3);
  if (count == 0) throw IoError(name + ": no vertices");
  mesh.vertices = Eigen::Map<const Eigen::Matrix3Xd>(geometry.positions.data(), 3, count);
  try {
    mesh.triangles = fanTriangulate(geometry.faces, count, [](const std::vector<long>& face) -> const auto& { return face; });
  } catch (const InvalidInputError& e) {
    throw IoError(name + ": " + e.what());
  }
  if (mesh.numTriangles() == 0) throw IoError(name + ": no triangles");
  return mesh;
}

}  // namespace deformation_enrichment::mesh
