#include "deformation_enrichment/elasticity/symmetric_eigen3.hpp"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <utility>

namespace deformation_enrichment::elasticity {

namespace {

constexpr double kTwoPiOverThree = 2.0943951023931954923;

// Any unit vector orthogonal to the unit vector u.
Eigen::Vector3d anyOrthogonal(const Eigen::Vector3d& u) {
  Eigen::Index smallest = 0;
  u.cwiseAbs().minCoeff(&smallest);
  const Eigen::Vector3d w = u.cross(Eigen::Vector3d::Unit(smallest));
  return w * (1.0 / w.norm());
}

}  // namespace

SymmetricEigen3 symmetricEigen3(const Eigen::Matrix3d& Ain) {
  Eigen::Matrix3d A;
  A << Ain(0, 0), Ain(0, 1), Ain(0, 2),  //
      Ain(0, 1), Ain(1, 1), Ain(1, 2),   //
      Ain(0, 2), Ain(1, 2), Ain(2, 2);
  // Squares of entries appear below: rescale outside [1e-100, 1e100] (no scaling in the normal range).
  const double maxAbs = A.cwiseAbs().maxCoeff();
  const bool rescale = maxAbs > 1e100 || (maxAbs < 1e-100 && maxAbs > 0.0);
  if (rescale) A /= maxAbs;

  SymmetricEigen3 out;
  // Deviatoric part B = A - m I, normalised by p = sqrt(tr(B^2) / 6): the eigenvalues of B / p are
  // 2 cos(phi + 2 pi k / 3) with phi = acos(det(B / p) / 2) / 3 (trigonometric solution of the cubic).
  const double m = A.trace() / 3.0;
  Eigen::Matrix3d B = A;
  B.diagonal().array() -= m;
  const double q = (B.diagonal().squaredNorm() + 2.0 * (B(0, 1) * B(0, 1) + B(0, 2) * B(0, 2) + B(1, 2) * B(1, 2))) / 6.0;
  if (q == 0.0) {  // A = m I
    out.values.setConstant(rescale ? m * maxAbs : m);
    out.vectors.setIdentity();
    return out;
  }
  const double p = std::sqrt(q);
  const double r = std::clamp(0.5 * (B * (1.0 / p)).determinant(), -1.0, 1.0);
  const double phi = std::acos(r) / 3.0;
  // Only the eigenvalue farthest from the mean is taken from the formula: it is isolated (gap >= sqrt(3) p)
  // and insensitive to rounding in r. The formula splits a (near-)double pair only to sqrt(eps), so the
  // other two come from the exact 2x2 problem on the orthogonal complement instead.
  const bool largestIsolated = r >= 0.0;
  const double shift = 2.0 * p * std::cos(largestIsolated ? phi : phi + kTwoPiOverThree);  // lambda - m
  Eigen::Matrix3d M = B;
  M.diagonal().array() -= shift;
  // Null vector of the rank-2 matrix M: the largest cross product of two of its rows.
  const Eigen::Vector3d c01 = M.row(0).cross(M.row(1)), c02 = M.row(0).cross(M.row(2)),
                        c12 = M.row(1).cross(M.row(2));
  const double n01 = c01.squaredNorm(), n02 = c02.squaredNorm(), n12 = c12.squaredNorm();
  Eigen::Vector3d e;
  if (n01 >= n02 && n01 >= n12) {
    e = c01 * (1.0 / std::sqrt(n01));
  } else if (n02 >= n12) {
    e = c02 * (1.0 / std::sqrt(n02));
  } else {
    e = c12 * (1.0 / std::sqrt(n12));
  }
  const Eigen::Vector3d b1 = anyOrthogonal(e);
  const Eigen::Vector3d b2 = e.cross(b1);
  // 2x2 block of B on (b1, b2), diagonalised by one exact Jacobi rotation: tan = t = 2 a12 sgn(d) / (|d| + h),
  // cos = sqrt((1 + |d| / h) / 2), d = a22 - a11, h = sqrt(d^2 + 4 a12^2).
  const Eigen::Vector3d Bb1 = B * b1, Bb2 = B * b2;
  const double a11 = b1.dot(Bb1), a22 = b2.dot(Bb2), a12 = b1.dot(Bb2);
  const double d = a22 - a11;
  const double h = std::sqrt(d * d + 4.0 * a12 * a12);
  double t = 0.0, c = 1.0;
  if (h > 0.0) {
    t = (d < 0.0 ? -2.0 * a12 : 2.0 * a12) / (h + std::abs(d));
    c = std::sqrt(0.5 + 0.5 * std::abs(d) / h);
  }
  const double s = t * c;
  double values[3] = {shift, a11 - t * a12, a22 + t * a12};
  Eigen::Vector3d vectors[3] = {e, c * b1 - s * b2, s * b1 + c * b2};
  // Sort ascending (three compare-swaps). (e, v1, v2) = (e, b1, b2) rotated: det +1; each swap flips it.
  bool odd = false;
  auto order = [&](int i, int j) {
    if (values[i] > values[j]) {
      std::swap(values[i], values[j]);
      std::swap(vectors[i], vectors[j]);
      odd = !odd;
    }
  };
  order(0, 1);
  order(1, 2);
  order(0, 1);
  for (int k = 0; k < 3; ++k) {
    out.values(k) = m + values[k];
    out.vectors.col(k) = vectors[k];
  }
  if (odd) out.vectors.col(0) *= -1.0;
  if (rescale) out.values *= maxAbs;
  return out;
}

}  // namespace deformation_enrichment::elasticity
