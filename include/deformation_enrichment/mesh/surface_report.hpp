#pragma once
// What a surface read from a file looks like before it is used: coincident vertices, zero-area triangles
// and the edge topology (open or closed, manifold, consistently oriented). Readers keep such surfaces
// as they are; callers decide (a display surface may be open, a surface to tetrahedralise may not).
#include <Eigen/Core>
#include <string>

#include "deformation_enrichment/mesh/triangle_mesh.hpp"

namespace deformation_enrichment::mesh {

struct SurfaceReport {
  Eigen::Index vertices = 0;
  Eigen::Index triangles = 0;
  Eigen::Index duplicateVertices = 0;    ///< vertices at exactly the position of an earlier vertex
  Eigen::Index unusedVertices = 0;       ///< vertices no triangle references
  Eigen::Index degenerateTriangles = 0;  ///< repeated corner or zero area (the test of validate)
  Eigen::Index boundaryEdges = 0;        ///< edges of one triangle (an open surface has them)
  Eigen::Index nonManifoldEdges = 0;     ///< edges of more than two triangles
  Eigen::Index misorientedEdges = 0;     ///< edges two triangles traverse in the same direction

  /// Closed, manifold and consistently oriented: what a tetrahedraliser needs.
  bool closedManifold() const { return boundaryEdges == 0 && nonManifoldEdges == 0 && misorientedEdges == 0; }
};

/// Counts the above; needs only indices in range (throws InvalidInputError otherwise).
SurfaceReport inspectSurface(const TriangleMesh& mesh);

/// One line for logs, e.g. "5000 vertices, 9996 triangles, closed manifold, 2 duplicate vertices".
std::string describe(const SurfaceReport& report);

}  // namespace deformation_enrichment::mesh
