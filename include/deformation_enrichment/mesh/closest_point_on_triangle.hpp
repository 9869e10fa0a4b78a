#pragma once
// The point of a triangle nearest to a query point, by the Voronoi-region case analysis of the triangle's
// vertices, edges and face (the standard construction, e.g. Ericson, Real-Time Collision Detection 5.1.5),
// and the barycentric coordinates of a point on a triangle.
#include <Eigen/Core>

namespace deformation_enrichment::mesh {

/// The point of triangle (a, b, c) nearest to p; a degenerate (zero-area) triangle that reaches the face
/// case returns a.
Eigen::Vector3d closestPointOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                       const Eigen::Vector3d& c);

/// Barycentric coordinates (>= 0, sum 1) of a point on triangle (a, b, c), from sub-triangle areas; a
/// degenerate (zero-area) triangle gives its corner nearest to the point.
Eigen::Vector3d barycentricOnTriangle(const Eigen::Vector3d& point, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                      const Eigen::Vector3d& c);

}  // namespace deformation_enrichment::mesh
