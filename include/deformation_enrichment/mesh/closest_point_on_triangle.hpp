#pragma once
// The point of a triangle nearest to a query point, by the Voronoi-region case analysis of the triangle's
// vertices, edges and face (the standard construction, e.g. Ericson, Real-Time Collision Detection 5.1.5).
#include <Eigen/Core>

namespace deformation_enrichment::mesh {

/// The point of triangle (a, b, c) nearest to p; a degenerate (zero-area) triangle that reaches the face
/// case returns a.
Eigen::Vector3d closestPointOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                       const Eigen::Vector3d& c);

}  // namespace deformation_enrichment::mesh
