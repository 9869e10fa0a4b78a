#include "deformation_enrichment/shape_space/dihedral_angle.hpp"

#include <cmath>

#include <Eigen/Geometry>
#include <unsupported/Eigen/AutoDiff>

namespace deformation_enrichment::shape_space {

namespace {

// Closed-form gradient of the hinge angle (Bridson et al. 2003, bending modes u1..u4; here with the sign of
// our theta): d theta/d x_k = -|e| n1/|n1|^2, d theta/d x_l = -|e| n2/|n2|^2, edge vertices by the
// projections of x_k and x_l onto the edge. Templated so its forward-mode derivative is the Hessian.
template <class T>
Eigen::Matrix<T, 12, 1> hingeGradient(const Eigen::Matrix<T, 3, 1>& xi, const Eigen::Matrix<T, 3, 1>& xj,
                                      const Eigen::Matrix<T, 3, 1>& xk, const Eigen::Matrix<T, 3, 1>& xl) {
  using std::sqrt;
  const Eigen::Matrix<T, 3, 1> e = xj - xi;
  const T edgeLength = sqrt(e.dot(e));
  const Eigen::Matrix<T, 3, 1> n1 = e.cross(xk - xi);
  const Eigen::Matrix<T, 3, 1> n2 = (xl - xi).cross(e);
  const Eigen::Matrix<T, 3, 1> s1 = n1 / n1.dot(n1);
  const Eigen::Matrix<T, 3, 1> s2 = n2 / n2.dot(n2);
  Eigen::Matrix<T, 12, 1> g;
  g.template segment<3>(0) = -(((xk - xj).dot(e) / edgeLength) * s1 + ((xl - xj).dot(e) / edgeLength) * s2);
  g.template segment<3>(3) = ((xk - xi).dot(e) / edgeLength) * s1 + ((xl - xi).dot(e) / edgeLength) * s2;
  g.template segment<3>(6) = -edgeLength * s1;
  g.template segment<3>(9) = -edgeLength * s2;
  return g;
}

}  // namespace

double dihedralAngle(const Eigen::Vector3d& xi, const Eigen::Vector3d& xj, const Eigen::Vector3d& xk,
                     const Eigen::Vector3d& xl) {
  const Eigen::Vector3d e = xj - xi;
  const Eigen::Vector3d n1 = e.cross(xk - xi);
  const Eigen::Vector3d n2 = (xl - xi).cross(e);
  return std::atan2(n1.cross(n2).dot(e) / e.norm(), n1.dot(n2));
}

Eigen::Vector2d dihedralAngleVector(const Eigen::Vector3d& xi, const Eigen::Vector3d& xj, const Eigen::Vector3d& xk,
                                    const Eigen::Vector3d& xl) {
  const Eigen::Vector3d e = xj - xi;
  const Eigen::Vector3d n1 = e.cross(xk - xi);
  const Eigen::Vector3d n2 = (xl - xi).cross(e);
  return {n1.cross(n2).dot(e), e.norm() * n1.dot(n2)};  // dihedralAngle's atan2 arguments times |e|
}

Eigen::Matrix<double, 12, 1> dihedralAngleGradient(const Eigen::Vector3d& xi, const Eigen::Vector3d& xj,
                                                   const Eigen::Vector3d& xk, const Eigen::Vector3d& xl) {
  return hingeGradient<double>(xi, xj, xk, xl);
}

double dihedralAngleAndGradient(const Eigen::Vector3d& xi, const Eigen::Vector3d& xj, const Eigen::Vector3d& xk,
                                const Eigen::Vector3d& xl, Eigen::Matrix<double, 12, 1>& gradient) {
  // The same formulas as dihedralAngle and hingeGradient, sharing e, |e|, n1 and n2.
  const Eigen::Vector3d e = xj - xi;
  const double edgeLength = e.norm();
  const Eigen::Vector3d n1 = e.cross(xk - xi);
  const Eigen::Vector3d n2 = (xl - xi).cross(e);
  const double n1Squared = n1.squaredNorm(), n2Squared = n2.squaredNorm();
  const Eigen::Vector3d s1 = n1 / n1Squared, s2 = n2 / n2Squared;
  const double inverseLength = 1.0 / edgeLength;
  const double ek = (xk - xi).dot(e) * inverseLength, el = (xl - xi).dot(e) * inverseLength;
  // (x_k - x_j).e / |e| = (x_k - x_i).e / |e| - |e| (likewise for l)
  gradient.segment<3>(0) = -((ek - edgeLength) * s1 + (el - edgeLength) * s2);
  gradient.segment<3>(3) = ek * s1 + el * s2;
  gradient.segment<3>(6) = -edgeLength * s1;
  gradient.segment<3>(9) = -edgeLength * s2;
  return std::atan2(n1.cross(n2).dot(e) * inverseLength, n1.dot(n2));
}

HingeAngle dihedralAngleDerivatives(const Eigen::Vector3d& xi, const Eigen::Vector3d& xj,
                                    const Eigen::Vector3d& xk, const Eigen::Vector3d& xl, bool withHessian) {
  HingeAngle result;
  result.theta = dihedralAngle(xi, xj, xk, xl);
  if (!withHessian) {
    result.gradient = hingeGradient<double>(xi, xj, xk, xl);
    result.hessian.setZero();
    return result;
  }
  // Forward-mode differentiation of the closed-form gradient gives the Hessian (one pass, 12 directions).
  using Dual = Eigen::AutoDiffScalar<Eigen::Matrix<double, 12, 1>>;
  const Eigen::Vector3d* points[4] = {&xi, &xj, &xk, &xl};
  Eigen::Matrix<Dual, 3, 1> p[4];
  for (int v = 0; v < 4; ++v) {
    for (int c = 0; c < 3; ++c) {
      p[v][c] = Dual((*points[v])[c], 12, 3 * v + c);
    }
  }
  const Eigen::Matrix<Dual, 12, 1> g = hingeGradient<Dual>(p[0], p[1], p[2], p[3]);
  for (int r = 0; r < 12; ++r) {
    result.gradient[r] = g[r].value();
    result.hessian.row(r) = g[r].derivatives().transpose();
  }
  // Exact Hessians are symmetric; symmetrising removes the rounding asymmetry of forward mode.
  result.hessian = 0.5 * (result.hessian + result.hessian.transpose()).eval();
  return result;
}

}  // namespace deformation_enrichment::shape_space
