#pragma once
// Repair of a dirty closed surface before it is tetrahedralised, with CGAL's Polygon Mesh Processing
// [CGAL-PMP]: real organ files (segmentation, SOFA, Blender, vendors) self-intersect, repeat vertices and
// triangles, have zero-area triangles, small holes and loose debris. A fine model conforming to such a
// surface cannot be built (tetgen refuses intersecting facets); the repaired surface can.
#include <Eigen/Core>
#include <string>

#include "deformation_enrichment/mesh/triangle_mesh.hpp"

namespace deformation_enrichment::mesh {

/// What repairSurface found and did, and whether the result can be tetrahedralised.
struct SurfaceRepairReport {
  Eigen::Index mergedVertices = 0;        ///< duplicate and unused vertices removed
  Eigen::Index removedTriangles = 0;      ///< repeated-corner, duplicate and zero-area triangles removed
  Eigen::Index splitVertices = 0;         ///< non-manifold vertices duplicated so the surface can be oriented
  Eigen::Index flippedTriangles = 0;      ///< triangles turned (or renumbered by a split) to agree with their neighbours
  Eigen::Index droppedComponents = 0;     ///< pieces below `minComponentShare` of the largest one's area
  Eigen::Index holesFilled = 0;           ///< boundary loops closed by triangulation
  Eigen::Index selfIntersections = 0;     ///< intersecting triangle pairs found (after the steps above)
  Eigen::Index selfIntersectionsLeft = 0; ///< intersecting triangle pairs the repair could not remove
  Eigen::Index boundaryEdgesLeft = 0;     ///< edges of one triangle left (0: closed)
  bool reoriented = false;                ///< triangles flipped so the surface faces outwards

  /// Closed and free of self-intersections: a tetrahedraliser can fill it.
  bool closedAndSelfIntersectionFree() const { return selfIntersectionsLeft == 0 && boundaryEdgesLeft == 0; }
  /// Nothing had to change.
  bool untouched() const {
    return mergedVertices == 0 && removedTriangles == 0 && splitVertices == 0 && flippedTriangles == 0 && droppedComponents == 0 && holesFilled == 0 &&
           selfIntersections == 0 && !reoriented;
  }
};

struct SurfaceRepairOptions {
  /// Components with less area than this share of the largest one are dropped as debris.
  double minComponentShare = 0.01;
};

struct SurfaceRepair {
  TriangleMesh surface;  ///< the input itself when nothing had to change (same vertex order)
  SurfaceRepairReport report;
};

/// Repairs `surface` in this order: duplicate vertices merged and repeated, duplicate or zero-area triangles
/// removed (polygon soup repair); non-manifold vertices split and orientation made consistent; debris
/// components dropped; every hole filled; self-intersections removed by autorefinement, or where that
/// fails by CGAL's local remeshing; finally faced outwards. The report says what is left when the surface
/// could not be made closed and free of self-intersections. Throws InvalidInputError for an empty surface,
/// non-finite positions, out-of-range indices, no triangle with area, or triangles that cannot be oriented.
SurfaceRepair repairSurface(const TriangleMesh& surface, const SurfaceRepairOptions& options = {});

/// Intersecting pairs of triangles (sharing a vertex or an edge is not an intersection). Throws as repairSurface.
Eigen::Index countSelfIntersections(const TriangleMesh& surface);

/// One line for logs: "repaired: 16 self-intersecting pairs, 0 holes, 2 duplicate vertices, ...; closed,
/// no self-intersection left" (or "clean: nothing to repair").
std::string describe(const SurfaceRepairReport& report);

}  // namespace deformation_enrichment::mesh
