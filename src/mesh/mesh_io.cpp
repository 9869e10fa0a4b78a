#include "deformation_enrichment/mesh/mesh_io.hpp"

#include <pcl/PolygonMesh.h>
#include <pcl/conversions.h>
#include <pcl/io/obj_io.h>
#include <pcl/io/ply_io.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <algorithm>
#include <cctype>
#include <fstream>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/obj_reader.hpp"
#include "deformation_enrichment/mesh/ply_reader.hpp"

namespace deformation_enrichment::mesh {
namespace {

enum class Format { Obj, Ply };

Format formatOf(const std::string& path) {
  const auto dot = path.find_last_of('.');
  std::string ext = dot == std::string::npos ? "" : path.substr(dot + 1);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext == "obj") return Format::Obj;
  if (ext == "ply") return Format::Ply;
  throw IoError("mesh file '" + path + "' has an unsupported extension (expected .obj or .ply)");
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

}  // namespace

TriangleMesh readTriangleMesh(const std::string& path) {
  const Format format = formatOf(path);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError("mesh file '" + path + "' cannot be opened");
  return format == Format::Obj ? readObj(in, path) : readPly(in, path);
}

void writeTriangleMesh(const std::string& path, const TriangleMesh& mesh) {
  const Format format = formatOf(path);
  validate(mesh, false);
  const pcl::PolygonMesh polygons = toPolygonMesh(mesh);
  const int status =
      format == Format::Obj ? pcl::io::saveOBJFile(path, polygons) : pcl::io::savePLYFileBinary(path, polygons);
  if (status < 0) throw IoError("mesh file '" + path + "' could not be written");
}

}  // namespace deformation_enrichment::mesh
