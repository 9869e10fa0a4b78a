#include "deformation_enrichment/mesh/triangle_mesh.hpp"

#include <Eigen/Geometry>
#include <string>

#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::mesh {

void validate(const TriangleMesh& mesh, bool requireNonDegenerate) {
  if (mesh.numVertices() == 0) throw InvalidInputError("triangle mesh has no vertices");
  if (mesh.numTriangles() == 0) throw InvalidInputError("triangle mesh has no triangles");
  for (Eigen::Index v = 0; v < mesh.numVertices(); ++v) {
    if (!mesh.vertices.col(v).allFinite())
      throw InvalidInputError("triangle mesh vertex " + std::to_string(v) + " is not finite");
  }
  const Eigen::Index n = mesh.numVertices();
  for (Eigen::Index t = 0; t < mesh.numTriangles(); ++t) {
    const Eigen::Vector3i tri = mesh.triangles.col(t);
    for (int k = 0; k < 3; ++k) {
      if (tri[k] < 0 || tri[k] >= n)
        throw InvalidInputError("triangle " + std::to_string(t) + " references vertex " +
                                std::to_string(tri[k]) + " but the mesh has " + std::to_string(n));
    }
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2])
      throw InvalidInputError("triangle " + std::to_string(t) + " repeats a vertex");
    if (requireNonDegenerate) {
      const Eigen::Vector3d a = mesh.vertices.col(tri[1]) - mesh.vertices.col(tri[0]);
      const Eigen::Vector3d b = mesh.vertices.col(tri[2]) - mesh.vertices.col(tri[0]);
      const double scale = std::max(a.squaredNorm(), b.squaredNorm());
      if (!(a.cross(b).norm() > 1e-12 * scale))
        throw InvalidInputError("triangle " + std::to_string(t) + " is degenerate (zero area)");
    }
  }
}

double enclosedVolume(const TriangleMesh& mesh) {
  double volume = 0.0;
  for (Eigen::Index t = 0; t < mesh.numTriangles(); ++t) {
    Eigen::Matrix3d corners;
    for (int k = 0; k < 3; ++k) corners.col(k) = mesh.vertices.col(mesh.triangles(k, t));
    volume += corners.determinant() / 6.0;
  }
  return volume;
}

Eigen::Matrix3Xd vertexNormals(const TriangleMesh& mesh) {
  Eigen::Matrix3Xd normals = Eigen::Matrix3Xd::Zero(3, mesh.numVertices());
  for (Eigen::Index t = 0; t < mesh.numTriangles(); ++t) {
    const Eigen::Vector3i tri = mesh.triangles.col(t);
    // The cross product's length is twice the area: summing it weights each face by its area.
    const Eigen::Vector3d areaNormal = (mesh.vertices.col(tri[1]) - mesh.vertices.col(tri[0]))
                                           .cross(mesh.vertices.col(tri[2]) - mesh.vertices.col(tri[0]));
    for (int k = 0; k < 3; ++k) normals.col(tri[k]) += areaNormal;
  }
  for (Eigen::Index v = 0; v < normals.cols(); ++v) {
    const double length = normals.col(v).norm();
    if (length > 0.0) normals.col(v) /= length;
  }
  return normals;
}

}  // namespace deformation_enrichment::mesh
