#pragma once
// Ghost mesh ([Brandt16 §6], "Energy and force approximation", after [vonTycowicz11]): a coarse version of the
// fine mesh made by half-edge collapses, so its vertices are a SUBSET of the fine vertices. A fine shape
// y = o + B q then has the ghost shape S y = S o + (S B) q, S the row selection of the kept vertices: the
// ghost subspace is isomorphic to the fine one (same reduced coordinates q), and the reduced energy and
// gradient are approximated by the ghost's, (S B)^T grad W~(S y_bar, S y).
#include <vector>

#include <Eigen/Core>

namespace deformation_enrichment::shape_space {

struct GhostMesh {
  std::vector<int> fineVertices;  ///< ghost vertex g is fine vertex fineVertices[g] (increasing)
  Eigen::Matrix3Xi triangles;     ///< over ghost vertex indices

  Eigen::Index numVertices() const { return Eigen::Index(fineVertices.size()); }
  /// S y: the ghost shape of a flat 3V fine shape.
  Eigen::VectorXd restrict(const Eigen::VectorXd& fine) const;
  /// S B: the rows of a 3V x d fine basis at the kept vertices.
  Eigen::MatrixXd restrictRows(const Eigen::MatrixXd& fine) const;
};

struct GhostMeshOptions {
  int targetVertices = 1250;  ///< [Brandt16 Table 1] used 1246-1252
  /// A collapse is refused if it leaves a triangle of its star with area / (sum of squared edge lengths)
  /// below this (equilateral: 0.144) or flips a triangle's normal, on the reference shape.
  double minTriangleQuality = 0.02;
};

/// Simplifies the oriented 2-manifold (with or without boundary) `triangles` at positions `reference`
/// (flat 3V) by shortest-edge-first half-edge collapses (CGAL Surface_mesh_simplification with a
/// placement that keeps one endpoint) until at most targetVertices remain or no collapse is allowed.
/// Boundary vertices are only collapsed along the boundary, so the outline survives. If the mesh already
/// has at most targetVertices vertices the ghost is the mesh itself (unused vertices dropped).
/// Throws InvalidInputError for sizes that do not match, non-finite positions, degenerate or
/// non-manifold triangles (naming the triangle), or targetVertices < 4.
GhostMesh ghostMesh(const Eigen::Matrix3Xi& triangles, const Eigen::VectorXd& reference,
                    const GhostMeshOptions& options = {});

}  // namespace deformation_enrichment::shape_space
