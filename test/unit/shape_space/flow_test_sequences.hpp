#pragma once
// Deformation sequences for the flow, averaging and geodesic tests: a bumpy sheet bent and stretched.
#include <cmath>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "shell_test_meshes.hpp"

namespace deformation_enrichment::shape_space::test {

/// Bends the sheet around the y axis with curvature kappa (arc length along x kept) and stretches y.
inline Eigen::VectorXd bent(const Eigen::VectorXd& flat, double kappa, double stretchY = 0.0) {
  Eigen::VectorXd out = flat;
  for (Eigen::Index v = 0; v < flat.size() / 3; ++v) {
    const double x = flat[3 * v] - 0.5, y = flat[3 * v + 1], z = flat[3 * v + 2];
    if (std::abs(kappa) < 1e-12) {
      out.segment<3>(3 * v) << x + 0.5, y * (1 + stretchY), z;
      continue;
    }
    const double theta = kappa * x, r = 1.0 / kappa - z;
    out.segment<3>(3 * v) << 0.5 + r * std::sin(theta), y * (1 + stretchY), 1.0 / kappa - r * std::cos(theta);
  }
  return out;
}

/// Rigid motion applied to a flat vector.
inline Eigen::VectorXd moved(const Eigen::VectorXd& x, const Eigen::Matrix3d& r, const Eigen::Vector3d& t) {
  Eigen::VectorXd out(x.size());
  for (Eigen::Index v = 0; v < x.size() / 3; ++v) out.segment<3>(3 * v) = r * x.segment<3>(3 * v) + t;
  return out;
}

inline Eigen::Matrix3d someRotation(double angle = 0.7) {
  return Eigen::AngleAxisd(angle, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
}

/// m shapes bending from kappa0 to kappa1 with noise of the given amplitude on the interior shapes.
inline std::vector<Eigen::VectorXd> noisyBending(const FlatMesh& base, int m, double kappa0, double kappa1,
                                                 double noise, unsigned seed) {
  std::vector<Eigen::VectorXd> shapes;
  for (int k = 0; k < m; ++k) {
    const double s = double(k) / (m - 1);
    Eigen::VectorXd x = bent(base.vertices, kappa0 + s * (kappa1 - kappa0), 0.1 * s);
    if (k > 0 && k + 1 < m && noise > 0) x = perturbed(x, noise, seed + unsigned(k));
    shapes.push_back(x);
  }
  return shapes;
}

}  // namespace deformation_enrichment::shape_space::test
