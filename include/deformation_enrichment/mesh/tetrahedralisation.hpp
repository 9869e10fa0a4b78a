#pragma once
// Tetrahedralisation of closed surfaces by Debian's `tetgen` [TetGen], run as a separate program (TetGen
// is AGPL-3: it is never linked into this BSD-3 package). The surface goes to tetgen as a .smesh in a
// temporary folder, the result comes back through readTetGen, and the folder is removed.
//
// Why tetgen rather than CGAL Mesh_3: `-Y` keeps the input triangles as the boundary, so a fine model
// conforms exactly to a display surface (Mesh_3 resamples the surface), no Mesh_3 templates enter the
// build, and tetgen -d names the intersecting facets of a bad surface.
#include <Eigen/Core>
#include <string>

#include "deformation_enrichment/mesh/edge_collapse.hpp"
#include "deformation_enrichment/mesh/tet_mesh.hpp"
#include "deformation_enrichment/mesh/triangle_mesh.hpp"

namespace deformation_enrichment::mesh {

struct TetrahedraliseOptions {
  double radiusEdgeRatio = 2.0;  ///< tetgen -q: largest circumradius / shortest edge (0: no quality refinement)
  double maxVolume = 0.0;        ///< tetgen -a: largest tet volume in m^3 (0: no limit)
  /// tetgen -Y: the boundary is exactly the input triangles (no Steiner points on it) and nodes
  /// 0..V-1 are the input vertices at their input positions.
  bool keepSurface = true;
  std::string program = "tetgen";  ///< found on PATH
};

struct Tetrahedralisation {
  TetMesh mesh;                  ///< positively oriented
  Eigen::Index surfaceVertices;  ///< with keepSurface: nodes [0, surfaceVertices) are the input vertices
  double seconds = 0.0;          ///< wall time of the whole call
  std::string command;           ///< the tetgen switches used, e.g. "-pzQFq2Y"
};

/// Tetrahedralises a closed, manifold, consistently oriented surface without duplicate or unused
/// vertices and zero-area triangles. Throws InvalidInputError naming what inspectSurface found for any
/// other surface, and with tetgen's own report (the intersecting facets) when tetgen fails, e.g. on a
/// self-intersecting surface; IoError when tetgen cannot be run; NumericalError if tetgen -Y moved the
/// surface.
Tetrahedralisation tetrahedralise(const TriangleMesh& closedSurface, const TetrahedraliseOptions& options = {});

struct CoarseVolumeOptions {
  EdgeCollapseOptions simplification{400, 0.02, -1.0};  ///< vertices of the coarse boundary
  TetrahedraliseOptions tetgen{2.0, 0.0, true};         ///< -Y: the boundary stays that coarse
  /// The simplified vertices lie on the input surface, so the coarse volume falls inside it where it is
  /// convex. When > 0, the boundary is moved out along its vertex normals by the distance within which
  /// this fraction of the input vertices outside the first coarse volume lie (0: not moved).
  double encloseFraction = 0.9;
};

struct CoarseVolume {
  Tetrahedralisation volume;      ///< its seconds cover simplification and every tetgen run
  TriangleMesh boundary;          ///< the simplified (and inflated) surface given to tetgen
  int targetVertices = 0;         ///< the simplification target that gave a surface tetgen accepted
  Eigen::Index boundaryVertices = 0;  ///< vertices of that simplified surface
  double inflation = 0.0;             ///< how far the boundary was moved out (metres)
};

/// A coarse volume for a scene that names no volume: the surface simplified by half-edge collapses
/// (its vertices a subset of the surface's), moved out to enclose most of it (encloseFraction), then
/// tetrahedralised. Collapses are checked only locally,
/// so a thin part may fold through itself: then the target grows by 25 % and the simplification is
/// repeated (at most 6 tries); an inflation that makes the boundary fold is halved (at most 4 times,
/// then none). Throws as tetrahedralise does, with the last tetgen report.
CoarseVolume coarseVolume(const TriangleMesh& closedSurface, const CoarseVolumeOptions& options = {});

}  // namespace deformation_enrichment::mesh
