#include "deformation_enrichment/elasticity/symmetric_eigen3.hpp"

#include <cmath>
#include <utility>

namespace deformation_enrichment::elasticity {

namespace {

// One Jacobi rotation annihilating a(p, q) (r is the third index): A <- J^T A J, V <- V J, by the smaller
// angle: tan = t = 2 a_pq sgn(d) / (|d| + h), cos = sqrt((1 + |d| / h) / 2), d = a_qq - a_pp,
// h = sqrt(d^2 + 4 a_pq^2). Entries are pre-scaled to at most 1e50, so d^2 cannot overflow.
template <int p, int q, int r>
inline void rotate(Eigen::Matrix3d& a, Eigen::Matrix3d& v) {
  const double apq = a(p, q);
  const double d = a(q, q) - a(p, p);
  const double absD = std::abs(d);
  const double h = std::sqrt(d * d + 4.0 * apq * apq);
  if (h == 0.0) return;
  const double t = (d < 0.0 ? -2.0 * apq : 2.0 * apq) / (absD + h);
  const double c = std::sqrt(0.5 + 0.5 * absD / h);
  const double s = t * c;
  a(p, p) -= t * apq;
  a(q, q) += t * apq;
  a(p, q) = a(q, p) = 0.0;
  const double arp = a(r, p);
  const double arq = a(r, q);
  a(r, p) = a(p, r) = c * arp - s * arq;
  a(r, q) = a(q, r) = s * arp + c * arq;
  for (int k = 0; k < 3; ++k) {
    const double vp = v(k, p);
    const double vq = v(k, q);
    v(k, p) = c * vp - s * vq;
    v(k, q) = s * vp + c * vq;
  }
}

}  // namespace

SymmetricEigen3 symmetricEigen3(const Eigen::Matrix3d& A) {
  Eigen::Matrix3d a;
  a << A(0, 0), A(0, 1), A(0, 2),  //
      A(0, 1), A(1, 1), A(1, 2),   //
      A(0, 2), A(1, 2), A(2, 2);
  // Squares appear in the rotation angle: rescale outside [1e-50, 1e50] (no scaling in the normal range).
  const double maxAbs = a.cwiseAbs().maxCoeff();
  const bool rescale = maxAbs > 1e50 || (maxAbs < 1e-50 && maxAbs > 0.0);
  if (rescale) a /= maxAbs;
  Eigen::Matrix3d v = Eigen::Matrix3d::Identity();
  // Cyclic sweeps until every off-diagonal entry is below 1e-17 |A| (absolute accuracy, which is what a
  // PSD clamp needs). Convergence is quadratic: 3-5 sweeps for any input; the cap of 32 is a safeguard.
  const double tolerance = 1e-34 * (a.diagonal().squaredNorm() + 2.0 * (a(0, 1) * a(0, 1) + a(0, 2) * a(0, 2) +
                                                                        a(1, 2) * a(1, 2)));
  auto negligible = [&](int p, int q) { return a(p, q) * a(p, q) <= tolerance; };
  for (int sweep = 0; sweep < 32; ++sweep) {
    bool rotated = false;
    if (!negligible(0, 1)) rotated = true, rotate<0, 1, 2>(a, v);
    if (!negligible(0, 2)) rotated = true, rotate<0, 2, 1>(a, v);
    if (!negligible(1, 2)) rotated = true, rotate<1, 2, 0>(a, v);
    if (!rotated) break;
  }
  SymmetricEigen3 out;
  out.values = rescale ? Eigen::Vector3d(maxAbs * a.diagonal()) : Eigen::Vector3d(a.diagonal());
  out.vectors = v;
  // Sort ascending; each column swap flips det(V), so negate a column after an odd number of swaps.
  bool odd = false;
  auto order = [&](int i, int j) {
    if (out.values(i) > out.values(j)) {
      std::swap(out.values(i), out.values(j));
      out.vectors.col(i).swap(out.vectors.col(j));
      odd = !odd;
    }
  };
  order(0, 1);
  order(1, 2);
  order(0, 1);
  if (odd) out.vectors.col(0) *= -1.0;
  return out;
}

}  // namespace deformation_enrichment::elasticity
