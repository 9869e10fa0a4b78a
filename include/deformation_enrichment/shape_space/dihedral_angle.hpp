#pragma once
// Signed dihedral angle of a hinge (two triangles sharing the edge x_i -> x_j, opposite vertices x_k and
// x_l) with its gradient and Hessian in the 12 coordinates (x_i, x_j, x_k, x_l). theta = 0 for a flat
// hinge; theta is the angle from the normal of (i, j, k) to the normal of (j, i, l) about the edge, so the
// result does not depend on how the second triangle is stored (consistent orientation is not required).
#include <cmath>

#include <Eigen/Core>
#include <Eigen/Geometry>

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

namespace detail {

// Closed-form gradient of the hinge angle (Bridson et al. 2003, bending modes u1..u4; here with the sign of
// our theta): d theta/d x_k = -|e| n1/|n1|^2, d theta/d x_l = -|e| n2/|n2|^2, edge vertices by the
// projections of x_k and x_l onto the edge. Returns dihedralAngle's atan2 arguments, which share e, |e|, n1, n2.
// Inline: the energies' element loops call it once per hinge and evaluation.
inline Eigen::Vector2d angleArgumentsAndGradient(const Eigen::Vector3d& xi, const Eigen::Vector3d& xj,
                                                 const Eigen::Vector3d& xk, const Eigen::Vector3d& xl,
                                                 Eigen::Matrix<double, 12, 1>& gradient) {
  const Eigen::Vector3d e = xj - xi, a = xk - xi, b = xl - xi;
  const double edgeLength = e.norm(), inverseLength = 1.0 / edgeLength;
  const Eigen::Vector3d n1 = e.cross(a), n2 = b.cross(e);
  const Eigen::Vector3d s1 = n1 / n1.squaredNorm(), s2 = n2 / n2.squaredNorm();
  const double ek = a.dot(e) * inverseLength, el = b.dot(e) * inverseLength;
  // (x_k - x_j).e / |e| = (x_k - x_i).e / |e| - |e| (likewise for l)
  gradient.segment<3>(0) = -((ek - edgeLength) * s1 + (el - edgeLength) * s2);
  gradient.segment<3>(3) = ek * s1 + el * s2;
  gradient.segment<3>(6) = -edgeLength * s1;
  gradient.segment<3>(9) = -edgeLength * s2;
  return {n1.cross(n2).dot(e) * inverseLength, n1.dot(n2)};
}

}  // namespace detail

/// theta and its gradient from one set of edge and normal vectors (the hot loops of gradient passes: the
/// separate calls above would form the cross products twice).
inline double dihedralAngleAndGradient(const Eigen::Vector3d& xi, const Eigen::Vector3d& xj, const Eigen::Vector3d& xk,
                                       const Eigen::Vector3d& xl, Eigen::Matrix<double, 12, 1>& gradient) {
  const Eigen::Vector2d arguments = detail::angleArgumentsAndGradient(xi, xj, xk, xl, gradient);
  return std::atan2(arguments[0], arguments[1]);
}

/// theta, its gradient and (if withHessian) its Hessian; without it the Hessian is set to zero.
HingeAngle dihedralAngleDerivatives(const Eigen::Vector3d& xi, const Eigen::Vector3d& xj,
                                    const Eigen::Vector3d& xk, const Eigen::Vector3d& xl, bool withHessian);

}  // namespace deformation_enrichment::shape_space
