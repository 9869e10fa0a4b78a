#pragma once
// Signed dihedral angle of a hinge (two triangles sharing the edge x_i -> x_j, opposite vertices x_k and
// x_l) with its gradient and Hessian in the 12 coordinates (x_i, x_j, x_k, x_l). theta = 0 for a flat
// hinge; theta is the angle from the normal of (i, j, k) to the normal of (j, i, l) about the edge, so the
// result does not depend on how the second triangle is stored (consistent orientation is not required).
#include <cmath>

#include <Eigen/Core>

namespace deformation_enrichment::shape_space {

/// theta with its derivatives; gradient and hessian are uninitialised until dihedralAngleDerivatives fills them
/// (hot loops construct many of these; zeroing a 12 x 12 matrix each time would cost as much as the angle).
struct HingeAngle {
  double theta = 0.0;
  Eigen::Matrix<double, 12, 1> gradient;
  Eigen::Matrix<double, 12, 12> hessian;
};

/// theta in (-pi, pi]. Preconditions (checked by the caller): both triangles non-degenerate.
double dihedralAngle(const Eigen::Vector3d& xi, const Eigen::Vector3d& xj, const Eigen::Vector3d& xk,
                     const Eigen::Vector3d& xl);

/// The gradient of theta alone (hot loops: no 12 x 12 Hessian to fill or copy).
Eigen::Matrix<double, 12, 1> dihedralAngleGradient(const Eigen::Vector3d& xi, const Eigen::Vector3d& xj,
                                                   const Eigen::Vector3d& xk, const Eigen::Vector3d& xl);

/// (|e| sin theta, |e| cos theta) up to a common positive factor: theta = atan2(result[0], result[1]).
Eigen::Vector2d dihedralAngleVector(const Eigen::Vector3d& xi, const Eigen::Vector3d& xj, const Eigen::Vector3d& xk,
                                    const Eigen::Vector3d& xl);

/// theta_a - theta_b wrapped into [-pi, pi] from the two hinges' angle vectors with one atan2 (the angle
/// of the rotation from b to a): equal to remainder(theta_a - theta_b, 2 pi) up to round-off.
inline double dihedralAngleDifference(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return std::atan2(a[0] * b[1] - a[1] * b[0], a[1] * b[1] + a[0] * b[0]);
}

/// theta and its gradient from one set of edge and normal vectors (the hot loops of gradient passes: the
/// separate calls above would form the cross products twice).
double dihedralAngleAndGradient(const Eigen::Vector3d& xi, const Eigen::Vector3d& xj, const Eigen::Vector3d& xk,
                                const Eigen::Vector3d& xl, Eigen::Matrix<double, 12, 1>& gradient);

/// theta, its gradient and (if withHessian) its Hessian; without it the Hessian is set to zero.
HingeAngle dihedralAngleDerivatives(const Eigen::Vector3d& xi, const Eigen::Vector3d& xj,
                                    const Eigen::Vector3d& xk, const Eigen::Vector3d& xl, bool withHessian);

}  // namespace deformation_enrichment::shape_space
