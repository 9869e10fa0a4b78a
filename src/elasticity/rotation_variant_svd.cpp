#include "deformation_enrichment/elasticity/rotation_variant_svd.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <utility>

#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::elasticity {

namespace {

// One-sided (Hestenes) Jacobi rotation of columns p, q of A (and V): A <- A J makes a_p and a_q
// orthogonal. The rotation is the symmetric Jacobi rotation of the 2x2 block of A^T A, but computed from
// the current columns each time, so no squared condition number enters: small singular values keep
// their relative accuracy. Returns false if the pair is already orthogonal to sqrt(3) eps relative (the
// convergence test of LAPACK's one-sided Jacobi, dgesvj, for 3 rows: a tighter one is below rounding and
// can rotate by rounding noise until the sweep cap).
template <int p, int q>
inline bool rotateColumns(Eigen::Matrix3d& A, Eigen::Matrix3d& V) {
  constexpr double kTolerance = 1.7320508075688772 * std::numeric_limits<double>::epsilon();
  const double alpha = A.col(p).squaredNorm();
  const double beta = A.col(q).squaredNorm();
  const double gamma = A.col(p).dot(A.col(q));
  if (gamma * gamma <= kTolerance * kTolerance * alpha * beta) return false;
  // tan(theta) = t = 2 gamma sgn(d) / (|d| + r), cos(theta) = sqrt((1 + |d| / r) / 2) with d = beta - alpha,
  // r = sqrt(d^2 + 4 gamma^2): the smaller Jacobi angle, with a sqrt-div-sqrt dependency chain only.
  const double d = beta - alpha;
  const double absD = std::abs(d);
  const double r = std::sqrt(d * d + 4.0 * gamma * gamma);
  const double t = (d < 0.0 ? -2.0 * gamma : 2.0 * gamma) / (absD + r);
  const double c = std::sqrt(0.5 + 0.5 * absD / r);
  const double s = t * c;
  for (int k = 0; k < 3; ++k) {
    const double ap = A(k, p), aq = A(k, q);
    A(k, p) = c * ap - s * aq;
    A(k, q) = s * ap + c * aq;
    const double vp = V(k, p), vq = V(k, q);
    V(k, p) = c * vp - s * vq;
    V(k, q) = s * vp + c * vq;
  }
  return true;
}

// Any unit vector orthogonal to the unit vector u (used when F has rank < 2).
Eigen::Vector3d anyOrthogonal(const Eigen::Vector3d& u) {
  Eigen::Index smallest = 0;
  u.cwiseAbs().minCoeff(&smallest);
  return u.cross(Eigen::Vector3d::Unit(smallest)).normalized();
}

}  // namespace

RotationVariantSvd rotationVariantSvd(const Eigen::Matrix3d& F) {
  if (!F.allFinite()) {
    throw InvalidInputError("rotationVariantSvd: deformation gradient has a non-finite entry");
  }
  // The rotation angles use fourth powers of the entries: rescale outside [1e-50, 1e50] so they neither
  // overflow nor underflow (no scaling, hence bit-exact behaviour, in the normal range).
  const double maxAbs = F.cwiseAbs().maxCoeff();
  const bool rescale = maxAbs > 1e50 || (maxAbs < 1e-50 && maxAbs > 0.0);
  Eigen::Matrix3d A = rescale ? Eigen::Matrix3d(F / maxAbs) : F;

  RotationVariantSvd out;
  out.V.setIdentity();
  // Cyclic one-sided Jacobi: A V converges to [sigma_0 u_0 | sigma_1 u_1 | sigma_2 u_2]. Quadratic
  // convergence, 3-5 sweeps in practice; the cap of 32 is a safeguard.
  for (int sweep = 0; sweep < 32; ++sweep) {
    bool rotated = rotateColumns<0, 1>(A, out.V);
    rotated = rotateColumns<0, 2>(A, out.V) || rotated;
    rotated = rotateColumns<1, 2>(A, out.V) || rotated;
    if (!rotated) break;
  }
  // Sort columns by norm, descending; a swap flips det(V), fixed below together with the sign of a_2.
  Eigen::Vector3d norms(A.col(0).squaredNorm(), A.col(1).squaredNorm(), A.col(2).squaredNorm());
  bool odd = false;
  auto order = [&](int i, int j) {
    if (norms(i) < norms(j)) {
      std::swap(norms(i), norms(j));
      A.col(i).swap(A.col(j));
      out.V.col(i).swap(out.V.col(j));
      odd = !odd;
    }
  };
  order(0, 1);
  order(1, 2);
  order(0, 1);
  if (odd) {
    out.V.col(2) *= -1.0;
    A.col(2) *= -1.0;
  }
  // U = [u_0, u_1, u_0 x u_1] is a rotation by construction; sigma_2 = u_2 . a_2 then carries the sign
  // of det F (rotation-variant SVD, [Masanti19 §2]).
  out.sigma(0) = std::sqrt(norms(0));
  out.sigma(1) = std::sqrt(norms(1));
  if (out.sigma(0) == 0.0) {
    out.U.setIdentity();
    out.sigma.setZero();
  } else {
    out.U.col(0) = A.col(0) / out.sigma(0);
    // Re-orthogonalise against u_0 (Jacobi leaves them orthogonal to 1e-16 relative only).
    const Eigen::Vector3d a1 = A.col(1) - out.U.col(0).dot(A.col(1)) * out.U.col(0);
    const double n1 = a1.norm();
    out.U.col(1) = n1 > 0.0 ? Eigen::Vector3d(a1 / n1) : anyOrthogonal(out.U.col(0));
    out.U.col(2) = out.U.col(0).cross(out.U.col(1));
    out.sigma(2) = out.U.col(2).dot(A.col(2));
  }
  if (rescale) out.sigma *= maxAbs;
  return out;
}

}  // namespace deformation_enrichment::elasticity
