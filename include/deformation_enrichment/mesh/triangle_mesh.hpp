#pragma once
// Triangle surface mesh: vertex positions (one column per vertex, metres) and triangles (vertex indices).
#include <Eigen/Core>

namespace deformation_enrichment::mesh {

struct TriangleMesh {
  Eigen::Matrix3Xd vertices;   ///< 3 x V positions
  Eigen::Matrix3Xi triangles;  ///< 3 x T vertex indices, counter-clockwise seen from outside

  Eigen::Index numVertices() const { return vertices.cols(); }
  Eigen::Index numTriangles() const { return triangles.cols(); }
};

/// Throws InvalidInputError naming the problem if the mesh is empty, has non-finite positions,
/// out-of-range or repeated indices in a triangle, or (when requireNonDegenerate) a zero-area triangle.
void validate(const TriangleMesh& mesh, bool requireNonDegenerate = true);

/// Volume a closed surface encloses (divergence theorem): positive when it faces outwards.
double enclosedVolume(const TriangleMesh& mesh);

/// Per-vertex area-weighted unit normals (zero vector for an isolated vertex).
Eigen::Matrix3Xd vertexNormals(const TriangleMesh& mesh);

}  // namespace deformation_enrichment::mesh
