#pragma once
// The volume state behind an embedded surface state: a simulator that publishes only its display surface
// (docs/coarse_simulator.md) gives the motion of points embedded in the coarse tets, not of the tets' nodes;
// a volume stamp needs the coarse displacement inside the volume too. The nodes' displacement u is fitted
// to the points' displacement d through the embedding W (d ~ W u, mesh::interpolate), with a membrane
// term over the tets' edges that carries the surface's motion into the interior where no point lies:
//   min_u |W u - d|^2 + s |G u|^2,   G: one row per tet edge, u_i - u_j;   fixed nodes at u = 0.
// s is relative (scaled by trace(W^T W) / trace(G^T G)), so the fit does not depend on the mesh's size.
#include <Eigen/Core>
#include <vector>

#include "deformation_enrichment/mesh/barycentric_embedding.hpp"
#include "deformation_enrichment/mesh/tet_mesh.hpp"

namespace deformation_enrichment::mesh {

/// Node displacements (3 x V) of `mesh` fitted to the displacements (3 x N) of the N points of `embedding`,
/// with the nodes `fixed` held at zero and relative smoothing `smoothing` (> 0). Throws InvalidInputError
/// for a column count that does not match the embedding, non-finite displacements, fixed ids outside the
/// mesh, a non-positive smoothing, or a system that has no unique solution (no fixed node and no point).
Eigen::Matrix3Xd fitNodeDisplacements(const TetMesh& mesh, const BarycentricEmbedding& embedding,
                                      const Eigen::Matrix3Xd& displacement, const std::vector<int>& fixed,
                                      double smoothing = 1e-3);

}  // namespace deformation_enrichment::mesh
