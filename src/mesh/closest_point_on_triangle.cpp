#include "deformation_enrichment/mesh/closest_point_on_triangle.hpp"

#include <Eigen/Geometry>

namespace deformation_enrichment::mesh {

Eigen::Vector3d closestPointOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                       const Eigen::Vector3d& c) {
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return a;
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return a + d1 / (d1 - d3) * ab;
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return a + d2 / (d2 - d6) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) return b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b);
  const double sum = va + vb + vc;
  if (!(sum > 0.0)) return a;  // degenerate (zero-area) triangle
  return a + ab * (vb / sum) + ac * (vc / sum);
}

Eigen::Vector3d barycentricOnTriangle(const Eigen::Vector3d& point, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                      const Eigen::Vector3d& c) {
  const Eigen::Vector3d n = (b - a).cross(c - a);
  const double area2 = n.squaredNorm();
  if (area2 > 0.0) {
    Eigen::Vector3d weights((b - point).cross(c - point).dot(n), (c - point).cross(a - point).dot(n),
                            (a - point).cross(b - point).dot(n));
    weights = weights.cwiseMax(0.0);
    const double sum = weights.sum();
    if (sum > 0.0) return weights / sum;
  }
  Eigen::Index corner = 0;
  Eigen::Vector3d((a - point).norm(), (b - point).norm(), (c - point).norm()).minCoeff(&corner);
  return Eigen::Vector3d::Unit(corner);
}

}  // namespace deformation_enrichment::mesh
