#pragma once
// Coarse-to-fine embedding: each fine point gets the coarse tet that contains it (or, when it lies
// slightly outside the coarse mesh, the tet it is closest to) and its barycentric coordinates there, so a
// coarse displacement field can be interpolated onto a fine surface (fine - coarse examples need this).
#include <Eigen/Core>

#include "deformation_enrichment/mesh/tet_mesh.hpp"

namespace deformation_enrichment::mesh {

struct BarycentricEmbedding {
  Eigen::VectorXi tet;       ///< per point: index of the coarse tet
  Eigen::Matrix4Xd weights;  ///< per point: barycentric coordinates (sum 1; slightly negative outside)
  Eigen::VectorXd outside;   ///< per point: distance to its tet (0 when inside)
};

/// Embeds `points` (3 x N) in `coarse`. A point outside every tet uses the nearest tet among those near
/// it (the affine extension of that tet). Throws InvalidInputError for an invalid
/// mesh, non-finite points, or a point farther than `maxOutside` (metres) from the coarse mesh.
BarycentricEmbedding embedPoints(const TetMesh& coarse, const Eigen::Matrix3Xd& points, double maxOutside);

/// Barycentric coordinates of p in tet t (may be negative; sum to one).
Eigen::Vector4d barycentricCoordinates(const TetMesh& mesh, Eigen::Index t, const Eigen::Vector3d& p);

/// Interpolates a per-vertex field of the coarse mesh (3 x V, e.g. a displacement) at the embedded points.
/// Exact for affine fields. Throws InvalidInputError if `field` does not have `coarseVertexCount` columns
/// or the embedding references a vertex beyond it.
Eigen::Matrix3Xd interpolate(const BarycentricEmbedding& embedding, const TetMesh& coarse, const Eigen::Matrix3Xd& field);

}  // namespace deformation_enrichment::mesh
