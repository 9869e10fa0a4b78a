#pragma once
// Coarse-to-fine embedding: each fine point gets the coarse tet that contains it (or, when it lies
// slightly outside the coarse mesh, the tet it is closest to) and its barycentric coordinates there, so a
// coarse displacement field can be interpolated onto a fine surface (fine - coarse examples need this).
#include <Eigen/Core>
#include <string>

#include "deformation_enrichment/mesh/tet_mesh.hpp"

namespace deformation_enrichment::mesh {

/// How far the embedded points lie outside the coarse mesh.
struct EmbeddingReport {
  Eigen::Index outside = 0;  ///< points outside every tet by more than 1e-9 of the mesh's bounding-box diagonal
  double maxDistance = 0.0;  ///< largest distance of a point to its tet (metres)
  double meanDistance = 0.0; ///< mean distance of the outside points (0 when none)
};

struct BarycentricEmbedding {
  Eigen::VectorXi tet;       ///< per point: index of the coarse tet
  Eigen::Matrix4Xd weights;  ///< per point: barycentric coordinates (sum 1; slightly negative outside)
  Eigen::VectorXd outside;   ///< per point: distance to its tet (0 when inside)
  EmbeddingReport report;
};

/// Embeds `points` (3 x N) in `coarse`. A point outside every tet is mapped to the tet nearest to it
/// with that tet's barycentric coordinates, some negative: the affine extension of the nearest tet, as
/// SOFA's BarycentricMapping does for points outside its mesh [SOFA-BarycentricMapping] (which picks the
/// tet with the nearest centroid; the nearest tet itself is picked here, so a point beside a small tet
/// next to a large one gets the small one). Throws InvalidInputError for an invalid mesh, non-finite
/// points, or points farther than `maxOutside` (metres) from the coarse mesh: the message says how many
/// and how far the farthest is.
/// With FarPoints::Skip, points farther than `maxOutside` are not refused but left out: tet -1, weights 0,
/// `outside` infinity (a grid around a surface, most of it in the air).
enum class FarPoints { Refuse, Skip };
BarycentricEmbedding embedPoints(const TetMesh& coarse, const Eigen::Matrix3Xd& points, double maxOutside,
                                 FarPoints far = FarPoints::Refuse);

/// One line for logs: "37 of 5000 points outside the coarse mesh, up to 0.0021 m (mean 0.0008 m)".
std::string describe(const EmbeddingReport& report, Eigen::Index points);

/// Barycentric coordinates of p in tet t (may be negative; sum to one).
Eigen::Vector4d barycentricCoordinates(const TetMesh& mesh, Eigen::Index t, const Eigen::Vector3d& p);

/// Interpolates a per-vertex field of the coarse mesh (3 x V, e.g. a displacement) at the embedded points
/// (zero at points left out). Exact for affine fields. Throws InvalidInputError if `field` does not have `coarseVertexCount` columns
/// or the embedding references a vertex beyond it.
Eigen::Matrix3Xd interpolate(const BarycentricEmbedding& embedding, const TetMesh& coarse, const Eigen::Matrix3Xd& field);

}  // namespace deformation_enrichment::mesh
