#pragma once
// Surface simplification by half-edge collapses (CGAL Surface_mesh_simplification [CGAL-SMS]) with a
// placement that keeps one endpoint, so the simplified vertices are a SUBSET of the input vertices at
// their own positions. Shared by the shape-space ghost mesh ([Brandt16 §6], shape_space/ghost_mesh.hpp)
// and coarse volumes made from a display surface (tetrahedralisation.hpp).
#include <Eigen/Core>
#include <vector>

#include "deformation_enrichment/mesh/triangle_mesh.hpp"

namespace deformation_enrichment::mesh {

struct EdgeCollapseOptions {
  int targetVertices = 0;  ///< stop at or below this many vertices (required, >= 4)
  /// A collapse is refused if it leaves a triangle of its star with area / (sum of squared edge lengths)
  /// below this (equilateral: 0.144) or flips a triangle's normal, on the reference shape.
  double minTriangleQuality = 0.02;
  /// ... or leaves two triangles around the kept vertex whose unit normals' dot product is below this:
  /// a fold (-1: no such check, as the ghost mesh has it).
  double minStarNormalCosine = -1.0;
};

struct EdgeCollapse {
  std::vector<int> keptVertices;  ///< simplified vertex k is input vertex keptVertices[k] (increasing)
  Eigen::Matrix3Xi triangles;     ///< over simplified vertex indices, orientation kept
};

/// Simplifies the oriented 2-manifold (with or without boundary) `triangles` at `reference` (3 x V) by
/// shortest-edge-first half-edge collapses until at most targetVertices remain or no collapse is
/// allowed. Boundary vertices are only collapsed along the boundary, so an outline survives. A mesh that
/// already has at most targetVertices vertices is kept (unused vertices dropped). Throws
/// InvalidInputError for non-finite positions, degenerate or non-manifold triangles (naming the
/// triangle), targetVertices < 4 or minTriangleQuality outside [0, 0.15).
EdgeCollapse collapseEdges(const Eigen::Matrix3Xi& triangles, const Eigen::Ref<const Eigen::Matrix3Xd>& reference,
                           const EdgeCollapseOptions& options);

/// collapseEdges on a surface, returned as a surface (the kept vertices in input order).
TriangleMesh simplifySurface(const TriangleMesh& surface, const EdgeCollapseOptions& options);

}  // namespace deformation_enrichment::mesh
