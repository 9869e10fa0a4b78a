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
#include "deformation_enrichment/mesh/point_cloud_layout.hpp"
#include "deformation_enrichment/mesh/triangle_mesh_from_cloud.hpp"

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

TriangleMesh fromPolygonMesh(const pcl::PolygonMesh& polygons, const std::string& path) {
  const pcl::PCLPointCloud2& cloud = polygons.cloud;
  PointCloudLayout layout;
  for (const auto& field : cloud.fields) layout.fields.push_back({field.name, field.offset, field.datatype, field.count});
  layout.width = cloud.width;
  layout.height = cloud.height;
  layout.pointStep = cloud.point_step;
  layout.rowStep = cloud.row_step;
  layout.isBigEndian = cloud.is_bigendian;
  TriangleMesh mesh;
  try {
    mesh = triangleMeshFromCloud(layout, cloud.data.data(), cloud.data.size(), polygons.polygons,
                                 [](const pcl::Vertices& polygon) -> const auto& { return polygon.vertices; });
  } catch (const InvalidInputError& e) {
    throw IoError("mesh file '" + path + "': " + e.what());
  }
  for (Eigen::Index v = 0; v < mesh.numVertices(); ++v)
    if (!mesh.vertices.col(v).allFinite()) throw IoError("mesh file '" + path + "': vertex " + std::to_string(v) + " is not finite");
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

}  // namespace

TriangleMesh readTriangleMesh(const std::string& path) {
  const Format format = formatOf(path);
  if (!std::ifstream(path).good()) throw IoError("mesh file '" + path + "' cannot be opened");
  pcl::PolygonMesh polygons;
  const int status =
      format == Format::Obj ? pcl::io::loadOBJFile(path, polygons) : pcl::io::loadPLYFile(path, polygons);
  if (status < 0) throw IoError("mesh file '" + path + "' could not be parsed");
  return fromPolygonMesh(polygons, path);
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
