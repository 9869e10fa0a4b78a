#include "deformation_enrichment/elasticity/symmetric_eigen3.hpp"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>
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

// The isolated eigenpair of a symmetric A (the eigenvalue farthest from the mean), in A's rescaled units.
struct IsolatedEigenpair {
  Eigen::Matrix3d B;      ///< deviatoric part of the rescaled A: A / scale - m I
  double m = 0.0;         ///< mean eigenvalue of A / scale
  double shift = 0.0;     ///< isolated eigenvalue of B (its eigenvalue of A / scale is m + shift)
  Eigen::Vector3d e;      ///< its unit eigenvector
  double p = 0.0;         ///< sqrt(tr(B^2) / 6), B's spread
  double scale = 1.0;     ///< A was divided by this (1 in the normal range)
  bool multipleOfIdentity = false;  ///< A = m I: no isolated eigenvalue
};

IsolatedEigenpair isolatedEigenpair(const Eigen::Matrix3d& Ain) {
  IsolatedEigenpair out;
  Eigen::Matrix3d& B = out.B;
  B << Ain(0, 0), Ain(0, 1), Ain(0, 2),  //
      Ain(0, 1), Ain(1, 1), Ain(1, 2),   //
      Ain(0, 2), Ain(1, 2), Ain(2, 2);
  // Squares of entries appear below: rescale outside [1e-100, 1e100] (no scaling in the normal range).
  const double maxAbs = B.cwiseAbs().maxCoeff();
  if (maxAbs > 1e100 || (maxAbs < 1e-100 && maxAbs > 0.0)) {
    out.scale = maxAbs;
    B /= maxAbs;
  }
  // Deviatoric part B = A - m I, normalised by p = sqrt(tr(B^2) / 6): the eigenvalues of B / p are
  // 2 cos(phi + 2 pi k / 3) with phi = acos(det(B / p) / 2) / 3 (trigonometric solution of the cubic).
  out.m = B.trace() / 3.0;
  B.diagonal().array() -= out.m;
  const double q = (B.diagonal().squaredNorm() + 2.0 * (B(0, 1) * B(0, 1) + B(0, 2) * B(0, 2) + B(1, 2) * B(1, 2))) / 6.0;
  if (q == 0.0) {
    out.multipleOfIdentity = true;
    return out;
  }
  const double p = out.p = std::sqrt(q);
  const double r = std::clamp(0.5 * (B * (1.0 / p)).determinant(), -1.0, 1.0);
  const double phi = std::acos(r) / 3.0;
  // Only the eigenvalue farthest from the mean is taken from the formula: it is isolated (gap >= sqrt(3) p)
  // and insensitive to rounding in r. The formula splits a (near-)double pair only to sqrt(eps), so
  // symmetricEigen3 takes the other two from the exact 2x2 problem on the orthogonal complement instead.
  const bool largestIsolated = r >= 0.0;
  out.shift = 2.0 * p * std::cos(largestIsolated ? phi : phi + kTwoPiOverThree);
  Eigen::Matrix3d M = B;
  M.diagonal().array() -= out.shift;
  // Null vector of the rank-2 matrix M: the largest cross product of two of its rows.
  const Eigen::Vector3d c01 = M.row(0).cross(M.row(1)), c02 = M.row(0).cross(M.row(2)),
                        c12 = M.row(1).cross(M.row(2));
  const double n01 = c01.squaredNorm(), n02 = c02.squaredNorm(), n12 = c12.squaredNorm();
  if (n01 >= n02 && n01 >= n12) {
    out.e = c01 * (1.0 / std::sqrt(n01));
  } else if (n02 >= n12) {
    out.e = c02 * (1.0 / std::sqrt(n02));
  } else {
    out.e = c12 * (1.0 / std::sqrt(n12));
  }
  return out;
}

// The full decomposition from the isolated eigenpair: the other two from the 2x2 problem on its complement.
SymmetricEigen3 completeDecomposition(const IsolatedEigenpair& iso) {
  SymmetricEigen3 out;
  if (iso.multipleOfIdentity) {
    out.values.setConstant(iso.m * iso.scale);
    out.vectors.setIdentity();
    return out;
  }
  const Eigen::Matrix3d& B = iso.B;
  const Eigen::Vector3d& e = iso.e;
  const double m = iso.m, shift = iso.shift;
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
  out.values *= iso.scale;
  return out;
}

}  // namespace

SymmetricEigen3 symmetricEigen3(const Eigen::Matrix3d& A) { return completeDecomposition(isolatedEigenpair(A)); }

Eigen::Matrix3d psdProjection3(const Eigen::Matrix3d& A) {
  const IsolatedEigenpair iso = isolatedEigenpair(A);
  if (iso.multipleOfIdentity) return Eigen::Matrix3d::Identity() * (std::max(iso.m, 0.0) * iso.scale);
  // The other two eigenvalues (in A's terms) have the sum tr(A) - isolated and the product
  // e_2(A) - isolated * sum, e_2 being the sum of A's principal 2x2 minors. If that product's sign is
  // certain beyond its rounding error and both share a sign, the projection changes at most the isolated
  // eigenvalue and the pair needs no eigenvectors; otherwise the full decomposition decides.
  const Eigen::Matrix3d As = iso.B + iso.m * Eigen::Matrix3d::Identity();
  const double isolated = iso.m + iso.shift;
  const double pairSum = 2.0 * iso.m - iso.shift;
  const double terms[6] = {As(0, 0) * As(1, 1), As(0, 0) * As(2, 2), As(1, 1) * As(2, 2),
                           -As(0, 1) * As(0, 1), -As(0, 2) * As(0, 2), -As(1, 2) * As(1, 2)};
  double e2 = 0.0, e2Magnitude = 0.0;
  for (double t : terms) {
    e2 += t;
    e2Magnitude += std::abs(t);
  }
  const double pairProduct = e2 - isolated * pairSum;
  const double roundingBound = 64.0 * std::numeric_limits<double>::epsilon() *
                               (e2Magnitude + (std::abs(isolated) + std::abs(pairSum)) * (std::abs(iso.m) + iso.p));
  if (pairProduct > roundingBound) {
    const Eigen::Matrix3d eeT = iso.e * iso.e.transpose();
    if (pairSum > 0.0) return (As - std::min(isolated, 0.0) * eeT) * iso.scale;  // pair > 0
    return (std::max(isolated, 0.0) * iso.scale) * eeT;                          // pair < 0
  }
  // The pair's signs differ, or their product is within its rounding: the full decomposition decides.
  const SymmetricEigen3 eig = completeDecomposition(iso);
  return eig.vectors * eig.values.cwiseMax(0.0).asDiagonal() * eig.vectors.transpose();
}

}  // namespace deformation_enrichment::elasticity
