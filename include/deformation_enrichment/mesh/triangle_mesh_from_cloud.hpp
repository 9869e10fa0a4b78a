#pragma once
// A triangle mesh from a polygon mesh as pcl_msgs/PolygonMesh and pcl::PolygonMesh store it: a vertex
// cloud (point_cloud_layout.hpp) plus polygons as vertex index lists, fan-triangulated.
#include <cstddef>
#include <cstdint>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/point_cloud_layout.hpp"
#include "deformation_enrichment/mesh/polygon_triangulation.hpp"
#include "deformation_enrichment/mesh/triangle_mesh.hpp"

namespace deformation_enrichment::mesh {

/// `cornersOf(polygon)` gives a polygon's vertex indices. Throws InvalidInputError naming the problem:
/// the cloud's (decodePositions), no vertex, an index outside the cloud, no polygon with three corners.
/// Positions are returned as stored; callers that need finite ones check (mesh::validate).
template <class PolygonRange, class CornersOf>
TriangleMesh triangleMeshFromCloud(const PointCloudLayout& layout, const std::uint8_t* data, std::size_t size,
                                   const PolygonRange& polygons, CornersOf cornersOf) {
  TriangleMesh mesh;
  mesh.vertices = decodePositions(layout, data, size).cast<double>();
  if (mesh.numVertices() == 0) throw InvalidInputError("mesh has no vertices");
  mesh.triangles = fanTriangulate(polygons, mesh.numVertices(), cornersOf);
  if (mesh.numTriangles() == 0) throw InvalidInputError("mesh has no triangles");
  return mesh;
}

}  // namespace deformation_enrichment::mesh
