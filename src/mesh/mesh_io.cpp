#include "deformation_enrichment/mesh/mesh_io.hpp"

#include <CGAL/IO/STL.h>
#include <CGAL/Simple_cartesian.h>
#include <pcl/PolygonMesh.h>
#include <pcl/conversions.h>
#include <pcl/io/obj_io.h>
#include <pcl/io/ply_io.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <fstream>
#include <iterator>
#include <new>
#include <sstream>
#include <vector>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/obj_reader.hpp"
#include "deformation_enrichment/mesh/off_reader.hpp"
#include "deformation_enrichment/mesh/ply_reader.hpp"
#include "deformation_enrichment/mesh/polygon_triangulation.hpp"

namespace deformation_enrichment::mesh {
namespace {

using CgalPoint = CGAL::Simple_cartesian<double>::Point_3;

/// Positions (checked finite) and fan-triangulated polygons as a mesh; `name` names the source in errors.
template <class Polygons, class CornersOf>
TriangleMesh assemble(Eigen::Matrix3Xd vertices, const Polygons& polygons, CornersOf cornersOf, const std::string& name) {
  TriangleMesh mesh;
  mesh.vertices = std::move(vertices);
  for (Eigen::Index v = 0; v < mesh.numVertices(); ++v)
    if (!mesh.vertices.col(v).allFinite())
      throw IoError("mesh file '" + name + "': vertex " + std::to_string(v) + " is not finite");
  try {
    mesh.triangles = fanTriangulate(polygons, mesh.numVertices(), cornersOf);
  } catch (const InvalidInputError& e) {
    throw IoError("mesh file '" + name + "': " + e.what());
  }
  if (mesh.numTriangles() == 0) throw IoError("mesh file '" + name + "' has no triangles");
  return mesh;
}

pcl::PolygonMesh toPolygonMesh(const TriangleMesh& mesh) {
  pcl::PointCloud<pcl::PointXYZ> cloud;
  cloud.resize(static_cast<size_t>(mesh.numVertices()));
  for (Eigen::Index v = 0; v < mesh.numVertices(); ++v)
    cloud[static_cast<size_t>(v)].getVector3fMap() = mesh.vertices.col(v).cast<float>();
  pcl::PolygonMesh polygons;
  pcl::toPCLPointCloud2(cloud, polygons.cloud);
  polygons.polygons.resize(static_cast<size_t>(mesh.numTriangles()));
  for (Eigen::Index t = 0; t < mesh.numTriangles(); ++t) {
    auto& corners = polygons.polygons[static_cast<size_t>(t)].vertices;
    for (int k = 0; k < 3; ++k) corners.push_back(static_cast<pcl::index_t>(mesh.triangles(k, t)));
  }
  return polygons;
}

/// Where a failed parse of `bytes` stopped: "line N" for text, "byte N" for binary STL.
std::string stopPosition(std::istringstream& parsed, const std::string& bytes, bool binary) {
  parsed.clear();
  const std::streamoff offset = parsed.tellg();
  size_t stop = offset < 0 ? bytes.size() : std::min(bytes.size(), static_cast<size_t>(offset));
  if (binary) return "byte " + std::to_string(stop);
  if (stop > 0 && bytes[stop - 1] == '\n') --stop;  // a reader that consumed a whole line failed on that line
  return "line " + std::to_string(1 + std::count(bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(stop), '\n'));
}

/// CGAL's STL polygon-soup reader (ASCII or binary) on the whole of `in`.
TriangleMesh readStl(std::istream& in, const std::string& name) {
  const std::string bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  if (in.bad()) throw IoError("mesh file '" + name + "' cannot be read");
  std::istringstream parsed(bytes, std::ios::in | std::ios::binary);
  std::vector<CgalPoint> points;
  std::vector<std::vector<std::size_t>> polygons;
  const bool binary = bytes.compare(0, 5, "solid") != 0;
  std::vector<std::array<std::size_t, 3>> triangles;
  bool ok = false;
  try {
    ok = CGAL::IO::read_STL(parsed, points, triangles, CGAL::parameters::verbose(false));
  } catch (const std::bad_alloc&) {
    throw IoError("mesh file '" + name + "': the counts in its header do not fit in memory");
  }
  for (const auto& t : triangles) polygons.emplace_back(t.begin(), t.end());
  if (!ok)
    throw IoError("mesh file '" + name + "' is not valid STL (CGAL's reader stopped at " + stopPosition(parsed, bytes, binary) + ")");
  Eigen::Matrix3Xd vertices(3, static_cast<Eigen::Index>(points.size()));
  for (size_t v = 0; v < points.size(); ++v)
    vertices.col(static_cast<Eigen::Index>(v)) << points[v].x(), points[v].y(), points[v].z();
  return assemble(std::move(vertices), polygons, [](const auto& polygon) -> const auto& { return polygon; }, name);
}

}  // namespace

SurfaceFormat surfaceFormatOf(const std::string& path) {
  const auto dot = path.find_last_of('.');
  std::string ext = dot == std::string::npos ? "" : path.substr(dot + 1);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext == "obj") return SurfaceFormat::Obj;
  if (ext == "ply") return SurfaceFormat::Ply;
  if (ext == "off") return SurfaceFormat::Off;
  if (ext == "stl") return SurfaceFormat::Stl;
  throw IoError("mesh file '" + path + "' has an unsupported extension (expected .obj, .ply, .off or .stl)");
}

TriangleMesh readTriangleMesh(std::istream& in, SurfaceFormat format, const std::string& name) {
  if (format == SurfaceFormat::Obj) return readObj(in, name);
  if (format == SurfaceFormat::Ply) return readPly(in, name);
  if (format == SurfaceFormat::Off) return readOff(in, name);
  return readStl(in, name);
}

TriangleMesh readTriangleMesh(const std::string& path) {
  const SurfaceFormat format = surfaceFormatOf(path);
  std::ifstream file(path, std::ios::binary);
  if (!file.good()) throw IoError("mesh file '" + path + "' cannot be opened");
  return readTriangleMesh(file, format, path);
}

void writeTriangleMesh(const std::string& path, const TriangleMesh& mesh) {
  const SurfaceFormat format = surfaceFormatOf(path);
  if (format != SurfaceFormat::Obj && format != SurfaceFormat::Ply)
    throw IoError("mesh file '" + path + "': only .obj and .ply are written");
  validate(mesh, false);
  const pcl::PolygonMesh polygons = toPolygonMesh(mesh);
  const int status =
      format == SurfaceFormat::Obj ? pcl::io::saveOBJFile(path, polygons) : pcl::io::savePLYFileBinary(path, polygons);
  if (status < 0) throw IoError("mesh file '" + path + "' could not be written");
}

}  // namespace deformation_enrichment::mesh
