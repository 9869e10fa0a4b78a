#pragma once
// Signed dihedral angle of a hinge (two triangles sharing the edge x_i -> x_j, opposite vertices x_k and
// x_l) with its gradient and Hessian in the 12 coordinates (x_i, x_j, x_k, x_l). theta = 0 for a flat
// hinge; theta is the angle from the normal of (i, j, k) to the normal of (j, i, l) about the edge, so the
// result does not depend on how the second triangle is stored (consistent orientation is not required).
#include <Eigen/Core>

namespace deformation_enrichment::shape_space {

struct HingeAngle {
  double theta = 0.0;
  Eigen::Matrix<double, 12, 1> gradient = Eigen::Matrix<double, 12, 1>::Zero();
  Eigen::Matrix<double, 12, 12> hessian = Eigen::Matrix<double, 12, 12>::Zero();
};

/// theta in (-pi, pi]. Preconditions (checked by the caller): both triangles non-degenerate.
double dihedralAngle(const Eigen::Vector3d& xi, const Eigen::Vector3d& xj, const Eigen::Vector3d& xk,
                     const Eigen::Vector3d& xl);

/// theta, its gradient and (if withHessian) its Hessian; the Hessian is left zero otherwise.
HingeAngle dihedralAngleDerivatives(const Eigen::Vector3d& xi, const Eigen::Vector3d& xj,
                                    const Eigen::Vector3d& xk, const Eigen::Vector3d& xl, bool withHessian);

}  // namespace deformation_enrichment::shape_space
