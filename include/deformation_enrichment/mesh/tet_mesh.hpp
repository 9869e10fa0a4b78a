#pragma once
// Tetrahedral volume mesh: vertex positions (one column per vertex, metres) and tets (vertex indices,
// positively oriented: det[x1-x0, x2-x0, x3-x0] > 0).
#include <Eigen/Core>

namespace deformation_enrichment::mesh {

struct TetMesh {
  Eigen::Matrix3Xd vertices;  ///< 3 x V positions
  Eigen::Matrix4Xi tets;      ///< 4 x T vertex indices

  Eigen::Index numVertices() const { return vertices.cols(); }
  Eigen::Index numTets() const { return tets.cols(); }
};

/// Throws InvalidInputError naming the problem if the mesh is empty, has non-finite positions,
/// out-of-range indices, or (when requireNonDegenerate) a tet with non-positive volume.
void validate(const TetMesh& mesh, bool requireNonDegenerate = true);

/// Signed volume of tet t.
double signedVolume(const TetMesh& mesh, Eigen::Index t);

/// Sum of the tets' signed volumes.
double totalVolume(const TetMesh& mesh);

/// Lumped vertex volumes: each vertex gets one quarter of the volume of every incident tet.
Eigen::VectorXd lumpedVertexVolumes(const TetMesh& mesh);

}  // namespace deformation_enrichment::mesh
