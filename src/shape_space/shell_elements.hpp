#pragma once
// Local terms of the Discrete Shells energies. Every membrane term and the bending weight are written as
// functions of squared edge lengths q (of the deformed and/or the reference shape): the derivatives in q
// come from second-order forward differentiation (Jet2), and the chain rule to vertex positions is exact
// and cheap because dq/dx = +-2 (x_a - x_b) and d^2q/dx^2 = +-2 I. Private to the shape_space module.
#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "deformation_enrichment/shape_space/discrete_shells.hpp"
#include "parallel_for.hpp"
#include "second_order_jet.hpp"

namespace deformation_enrichment::shape_space::detail {

/// A triangle whose area is below this times its summed squared edge lengths is degenerate (discrete_shells.hpp).
constexpr double kDegenerateAreaRatio = 1e-8;


/// a - 2 pi k in [-pi, pi], for a difference of angles (|a| below a few pi): the bending terms' wrapped angle
/// difference without std::remainder (measured: remainder was a tenth of an eq. 10 evaluation).
inline double wrappedAngle(double a) {
  while (a > M_PI) a -= 2.0 * M_PI;
  while (a < -M_PI) a += 2.0 * M_PI;
  return a;
}

/// Which outputs an evaluation needs (bit flags).
enum Need : unsigned {
  kValue = 1u,
  kGradientDeformed = 2u,
  kGradientReference = 4u,
  kHessianDeformed = 8u,
  kHessianMixed = 16u,
  kHessianReference = 32u,
};
constexpr unsigned kAnyHessian = kHessianDeformed | kHessianMixed | kHessianReference;

/// Value and derivatives of one local term over NV vertices; rows of hessianMixed index the reference.
/// Only the parts named in reset(need) are initialised (zeroing unused 12 x 12 blocks costs more than
/// some terms themselves).
template <int NV>
struct LocalTerm {
  static constexpr int D = 3 * NV;
  double value = 0.0;
  Eigen::Matrix<double, D, 1> gradientDeformed, gradientReference;
  Eigen::Matrix<double, D, D> hessianDeformed, hessianMixed, hessianReference;

  explicit LocalTerm(unsigned need) {
    if (need & kGradientDeformed) gradientDeformed.setZero();
    if (need & kGradientReference) gradientReference.setZero();
    if (need & kHessianDeformed) hessianDeformed.setZero();
    if (need & kHessianMixed) hessianMixed.setZero();
    if (need & kHessianReference) hessianReference.setZero();
  }
};

using LocalEdge = std::array<int, 2>;

// Adds a local 3NV x 3NV block matrix into the pattern's value array. Column 3 vb + d of the pattern holds
// the rows 3 va + r of every neighbour va of vb (sorted), so the entry sits at
// outer[3 vb + d] + 3 rank(va among vb's neighbours) + r.
template <int NV>
void scatterHessian(const Eigen::Matrix<double, 3 * NV, 3 * NV>& local, const std::array<int, NV>& vertices,
                    const HessianPattern& pattern, double* values) {
  for (int b = 0; b < NV; ++b) {
    const int vb = vertices[b];
    const int* neighboursBegin = pattern.neighbours.data() + pattern.neighbourStart[vb];
    const int* neighboursEnd = pattern.neighbours.data() + pattern.neighbourStart[vb + 1];
    for (int a = 0; a < NV; ++a) {
      const int rank = static_cast<int>(std::lower_bound(neighboursBegin, neighboursEnd, vertices[a]) - neighboursBegin);
      for (int d = 0; d < 3; ++d) {
        double* column = values + pattern.outer[3 * vb + d] + 3 * rank;
        for (int r = 0; r < 3; ++r) column[r] += local(3 * a + r, 3 * b + d);
      }
    }
  }
}


/// Triangle area from squared edge lengths by Kahan's stable form of Heron's formula (accurate for slivers).
template <class T>
T triangleArea(const T& q0, const T& q1, const T& q2) {
  using std::sqrt;
  T a = sqrt(q0), b = sqrt(q1), c = sqrt(q2);
  if (valueOf(a) < valueOf(b)) std::swap(a, b);
  if (valueOf(b) < valueOf(c)) std::swap(b, c);
  if (valueOf(a) < valueOf(b)) std::swap(a, b);
  return 0.25 * sqrt((a + (b + c)) * (c - (a - b)) * (c + (a - b)) * (a + (b - c)));
}

/// [Heeren12 eq. 8] per face: a_bar W(tr G, det G), G = g_bar^-1 g, with
/// W(a, d) = mu/2 a + lambda/4 d - (mu/2 + lambda/4) log d - mu - lambda/4. q = (deformed 0..2, reference 0..2),
/// edge m of both triangles opposite the same corner; tr G by the cotangent formula in squared lengths.
template <class T>
T hyperelasticMembrane(const std::array<T, 6>& q, double mu, double lambda) {
  using std::log;
  const T areaDeformed = triangleArea(q[0], q[1], q[2]);
  const T areaReference = triangleArea(q[3], q[4], q[5]);
  const T traceTerm = q[0] * (q[4] + q[5] - q[3]) + q[1] * (q[5] + q[3] - q[4]) + q[2] * (q[3] + q[4] - q[5]);
  const T traceG = traceTerm / (8.0 * areaReference * areaReference);
  const T areaRatio = areaDeformed / areaReference;
  const T detG = areaRatio * areaRatio;
  return areaReference * (0.5 * mu * traceG + 0.25 * lambda * detG - (0.5 * mu + 0.25 * lambda) * (2.0 * log(areaRatio)) -
                          mu - 0.25 * lambda);
}

/// Adds sum_m dq[m] d2q_m/dx2 + dAreaSquared d2(A^2)/dx2 + dLogAreaSquared d2(log A^2)/dx2 of triangle x to h
/// (q_m the squared length of the edge opposite corner m, A the area): the deformed Hessian of the hyperelastic
/// membrane in closed form (measured: a fifth of the jets' cost). With e1 = x1 - x0, e2 = x2 - x0,
/// A^2 = (|e1|^2 |e2|^2 - (e1.e2)^2) / 4, and d2(log A^2) = d2(A^2) / A^2 - d(A^2) d(A^2)^T / A^4.
inline void addFaceHessian(const std::array<Eigen::Vector3d, 3>& x, const std::array<double, 3>& dq, double dAreaSquared,
                           double dLogAreaSquared, Eigen::Matrix<double, 9, 9>& h) {
  const Eigen::Vector3d e1 = x[1] - x[0], e2 = x[2] - x[0];
  const double q1 = e1.squaredNorm(), q2 = e2.squaredNorm(), p = e1.dot(e2);
  const double areaSquared = 0.25 * (q1 * q2 - p * p);
  const Eigen::Matrix3d identity = Eigen::Matrix3d::Identity();
  // d2(A^2) in (e1, e2), then in (x0, x1, x2) by e1 = x1 - x0, e2 = x2 - x0.
  const Eigen::Matrix3d h11 = 0.5 * (q2 * identity - e2 * e2.transpose());
  const Eigen::Matrix3d h22 = 0.5 * (q1 * identity - e1 * e1.transpose());
  const Eigen::Matrix3d h12 = 0.5 * (2.0 * e1 * e2.transpose() - e2 * e1.transpose() - p * identity);  // d/de2 of d/de1
  Eigen::Matrix<double, 9, 9> areaHessian;
  areaHessian.block<3, 3>(3, 3) = h11;
  areaHessian.block<3, 3>(6, 6) = h22;
  areaHessian.block<3, 3>(3, 6) = h12;
  areaHessian.block<3, 3>(6, 3) = h12.transpose();
  areaHessian.block<3, 3>(0, 3) = -(h11 + h12.transpose());
  areaHessian.block<3, 3>(0, 6) = -(h12 + h22);
  areaHessian.block<3, 3>(3, 0) = areaHessian.block<3, 3>(0, 3).transpose();
  areaHessian.block<3, 3>(6, 0) = areaHessian.block<3, 3>(0, 6).transpose();
  areaHessian.block<3, 3>(0, 0) = h11 + h22 + h12 + h12.transpose();
  Eigen::Matrix<double, 9, 1> areaGradient;
  areaGradient.segment<3>(3) = 0.5 * (q2 * e1 - p * e2);
  areaGradient.segment<3>(6) = 0.5 * (q1 * e2 - p * e1);
  areaGradient.segment<3>(0) = -(areaGradient.segment<3>(3) + areaGradient.segment<3>(6));
  h += (dAreaSquared + dLogAreaSquared / areaSquared) * areaHessian -
       (dLogAreaSquared / (areaSquared * areaSquared)) * areaGradient * areaGradient.transpose();
  for (int m = 0; m < 3; ++m) {  // d2q_m/dx2 = 2 [[I, -I], [-I, I]] on the corners m + 1, m + 2
    const int b = 3 * ((m + 1) % 3), c = 3 * ((m + 2) % 3);
    const Eigen::Matrix3d block = (2.0 * dq[size_t(m)]) * identity;
    h.block<3, 3>(b, b) += block;
    h.block<3, 3>(c, c) += block;
    h.block<3, 3>(b, c) -= block;
    h.block<3, 3>(c, b) -= block;
  }
}

/// hyperelasticMembrane with its value, gradients and deformed Hessian in closed form (the passes without
/// mixed or reference Hessians; measured: the jets were the largest part of a gradient pass). With e_m the edge opposite corner m, n = (x1 - x0) x
/// (x2 - x0), A^2 = |n|^2 / 4 and P = sum_m q_m (q_bar_m+1 + q_bar_m+2 - q_bar_m) (= 8 A_bar^2 tr G, symmetric
/// in q and q_bar), the face energy is mu P / (16 A_bar) + lambda A^2 / (4 A_bar) - kappa A_bar log(A^2 / A_bar^2)
/// - (mu + lambda / 4) A_bar, kappa = mu / 2 + lambda / 4; dq_m/dx_(m+1) = 2 e_m = -dq_m/dx_(m+2) and
/// d(A^2)/dx_a = n x (x_(a+2) - x_(a+1)) / 2.
inline void addHyperelasticFace(const std::array<Eigen::Vector3d, 3>& x, const std::array<Eigen::Vector3d, 3>& xBar,
                                double mu, double lambda, unsigned need, LocalTerm<3>& out) {
  const std::array<Eigen::Vector3d, 3> e{x[1] - x[2], x[2] - x[0], x[0] - x[1]};
  const std::array<Eigen::Vector3d, 3> eBar{xBar[1] - xBar[2], xBar[2] - xBar[0], xBar[0] - xBar[1]};
  const Eigen::Vector3d n = e[2].cross(-e[1]), nBar = eBar[2].cross(-eBar[1]);
  const std::array<double, 3> q{e[0].squaredNorm(), e[1].squaredNorm(), e[2].squaredNorm()};
  const std::array<double, 3> qBar{eBar[0].squaredNorm(), eBar[1].squaredNorm(), eBar[2].squaredNorm()};
  const auto cotangentWeights = [](const std::array<double, 3>& r) {
    return std::array<double, 3>{r[1] + r[2] - r[0], r[2] + r[0] - r[1], r[0] + r[1] - r[2]};
  };
  const std::array<double, 3> c = cotangentWeights(qBar), cDeformed = cotangentWeights(q);
  const double p = q[0] * c[0] + q[1] * c[1] + q[2] * c[2];
  const double areaSquared = 0.25 * n.squaredNorm(), areaBar = 0.5 * nBar.norm();
  const double kappa = 0.5 * mu + 0.25 * lambda;
  const double logRatio = std::log(areaSquared / (areaBar * areaBar));
  out.value += mu * p / (16.0 * areaBar) + lambda * areaSquared / (4.0 * areaBar) - kappa * areaBar * logRatio -
               (mu + 0.25 * lambda) * areaBar;
  if (need & kGradientDeformed) {
    const double lengthFactor = mu / (16.0 * areaBar);                              // dW/dq_m = lengthFactor c_m
    const double areaFactor = lambda / (4.0 * areaBar) - kappa * areaBar / areaSquared;  // dW/d(A^2)
    for (int a = 0; a < 3; ++a) {
      const int m1 = (a + 1) % 3, m2 = (a + 2) % 3;
      out.gradientDeformed.segment<3>(3 * a) +=
          2.0 * lengthFactor * (c[m2] * e[m2] - c[m1] * e[m1]) + (0.5 * areaFactor) * n.cross(-e[a]);
    }
  }
  if (need & kHessianDeformed) {
    const double lengthFactor = mu / (16.0 * areaBar);
    addFaceHessian(x, {lengthFactor * c[0], lengthFactor * c[1], lengthFactor * c[2]}, lambda / (4.0 * areaBar),
                   -kappa * areaBar, out.hessianDeformed);
  }
  if (need & kGradientReference) {
    const double lengthFactor = mu / (16.0 * areaBar);  // dW/dq_bar_m = lengthFactor cDeformed_m
    const double dArea = -mu * p / (16.0 * areaBar * areaBar) - lambda * areaSquared / (4.0 * areaBar * areaBar) -
                         kappa * logRatio + 2.0 * kappa - (mu + 0.25 * lambda);  // dW/dA_bar
    const Eigen::Vector3d halfNormal = nBar / (2.0 * nBar.norm());                 // dA_bar/dx_a = halfNormal x (...)
    for (int a = 0; a < 3; ++a) {
      const int m1 = (a + 1) % 3, m2 = (a + 2) % 3;
      out.gradientReference.segment<3>(3 * a) +=
          2.0 * lengthFactor * (cDeformed[m2] * eBar[m2] - cDeformed[m1] * eBar[m1]) + dArea * halfNormal.cross(-eBar[a]);
    }
  }
}

/// [Grinspun03] edge term: k_L (1 - |e|/|e_bar|)^2 |e_bar|, q = (deformed, reference).
template <class T>
T discreteShellsEdge(const std::array<T, 2>& q, double kL) {
  using std::sqrt;
  const T referenceLength = sqrt(q[1]);
  const T strain = 1.0 - sqrt(q[0]) / referenceLength;
  return kL * strain * strain * referenceLength;
}

/// [Grinspun03] area term: k_A (1 - A/A_bar)^2 A_bar, q = (deformed 0..2, reference 0..2).
template <class T>
T discreteShellsArea(const std::array<T, 6>& q, double kA) {
  const T areaReference = triangleArea(q[3], q[4], q[5]);
  const T strain = 1.0 - triangleArea(q[0], q[1], q[2]) / areaReference;
  return kA * strain * strain * areaReference;
}

/// Bending weight c |e_bar|^2 / (A_bar_1 + A_bar_2) of a hinge (i, j, k, l), q = |ij|^2, |jk|^2, |ki|^2, |il|^2, |lj|^2.
/// c = 3 is [Grinspun03]'s |e_bar| / h_bar_e with h_bar_e a third of the average height of the two triangles; c = 1 is GOAST's.
template <class T>
T hingeWeight(const std::array<T, 5>& q, double c) {
  return c * q[0] / (triangleArea(q[0], q[1], q[2]) + triangleArea(q[0], q[3], q[4]));
}

/// hingeWeight(q, c) and, if gradient is given, its derivative in the 12 coordinates of the hinge x in closed form
/// (measured: the jets were an eighth of a gradient pass): w = c q0 / (A1 + A2) with triangles (i, j, k) and
/// (i, j, l), dA/dx_a = n_hat x (x_c - x_b) / 2 for (a, b, c) cyclic.
inline double hingeWeightAndGradient(const std::array<Eigen::Vector3d, 4>& x, double c,
                                     Eigen::Matrix<double, 12, 1>* gradient) {
  const Eigen::Vector3d e = x[1] - x[0];
  const Eigen::Vector3d m1 = e.cross(x[2] - x[0]), m2 = e.cross(x[3] - x[0]);
  const double twiceA1 = m1.norm(), twiceA2 = m2.norm(), areaSum = 0.5 * (twiceA1 + twiceA2);
  const double w = c * e.squaredNorm() / areaSum;
  if (gradient) {
    const Eigen::Vector3d h1 = m1 / (2.0 * twiceA1), h2 = m2 / (2.0 * twiceA2);  // n_hat / 2
    const double lengthFactor = 2.0 * c / areaSum, areaFactor = -w / areaSum;
    gradient->segment<3>(0) = -lengthFactor * e + areaFactor * (h1.cross(x[2] - x[1]) + h2.cross(x[3] - x[1]));
    gradient->segment<3>(3) = lengthFactor * e + areaFactor * (h1.cross(x[0] - x[2]) + h2.cross(x[0] - x[3]));
    gradient->segment<3>(6) = areaFactor * h1.cross(e);
    gradient->segment<3>(9) = areaFactor * h2.cross(e);
  }
  return w;
}

/// Chain rule from derivatives in the squared edge lengths (value, g, H) to the vertex positions.
template <int NV, int ND, int NR>
void chainToPositions(double value, const Eigen::Matrix<double, ND + NR, 1>& g,
                      const Eigen::Matrix<double, ND + NR, ND + NR>& H,
                      const std::array<Eigen::Vector3d, ND + NR>& edgeVectors,
                      const std::array<LocalEdge, ND>& deformedEdges, const std::array<LocalEdge, NR>& referenceEdges,
                      unsigned need, double weight, LocalTerm<NV>& out) {
  constexpr int N = ND + NR;
  constexpr int D = 3 * NV;
  out.value += weight * value;
  if ((need & kAnyHessian) == 0u) {
    // Gradients only: dq_m/dx = +-2 e_m on the edge's two vertices, added directly (no dense Jacobian;
    // measured: the dense path was the largest single cost of gradient passes).
    for (int m = 0; m < N; ++m) {
      const bool deformedLength = m < ND;
      if (!(need & (deformedLength ? kGradientDeformed : kGradientReference)) || g[m] == 0.0) continue;
      const LocalEdge& edge = deformedLength ? deformedEdges[m] : referenceEdges[m - ND];
      auto& gradient = deformedLength ? out.gradientDeformed : out.gradientReference;
      const Eigen::Vector3d d = (2.0 * weight * g[m]) * edgeVectors[m];
      gradient.template segment<3>(3 * edge[0]) += d;
      gradient.template segment<3>(3 * edge[1]) -= d;
    }
    return;
  }
  // Jacobian dq/dx of the deformed (rows 0..ND-1) and reference (rows ND..N-1) squared lengths.
  Eigen::Matrix<double, N, D> jacobian = Eigen::Matrix<double, N, D>::Zero();
  for (int m = 0; m < N; ++m) {
    const LocalEdge& edge = m < ND ? deformedEdges[m] : referenceEdges[m - ND];
    jacobian.template block<1, 3>(m, 3 * edge[0]) = 2.0 * edgeVectors[m].transpose();
    jacobian.template block<1, 3>(m, 3 * edge[1]) = -2.0 * edgeVectors[m].transpose();
  }
  // d^2 q_m / dx^2 = 2 [[I, -I], [-I, I]] on the edge's two vertices, weighted by df/dq_m.
  auto addLengthCurvature = [&](Eigen::Matrix<double, D, D>& h, const LocalEdge& edge, double dfdq) {
    const double s = 2.0 * weight * dfdq;
    for (int c = 0; c < 3; ++c) {
      h(3 * edge[0] + c, 3 * edge[0] + c) += s;
      h(3 * edge[1] + c, 3 * edge[1] + c) += s;
      h(3 * edge[0] + c, 3 * edge[1] + c) -= s;
      h(3 * edge[1] + c, 3 * edge[0] + c) -= s;
    }
  };
  const auto jacobianDeformed = jacobian.template topRows<ND>();
  const auto jacobianReference = jacobian.template bottomRows<NR>();
  if (need & kGradientDeformed) out.gradientDeformed += weight * jacobianDeformed.transpose() * g.template head<ND>();
  if (need & kGradientReference) out.gradientReference += weight * jacobianReference.transpose() * g.template tail<NR>();
  if (need & kHessianDeformed) {
    out.hessianDeformed += weight * jacobianDeformed.transpose() * H.template topLeftCorner<ND, ND>() * jacobianDeformed;
    for (int m = 0; m < ND; ++m) addLengthCurvature(out.hessianDeformed, deformedEdges[m], g[m]);
  }
  if (need & kHessianMixed) {
    out.hessianMixed += weight * jacobianReference.transpose() * H.template bottomLeftCorner<NR, ND>() * jacobianDeformed;
  }
  if (need & kHessianReference) {
    out.hessianReference +=
        weight * jacobianReference.transpose() * H.template bottomRightCorner<NR, NR>() * jacobianReference;
    for (int m = 0; m < NR; ++m) addLengthCurvature(out.hessianReference, referenceEdges[m], g[ND + m]);
  }
}

/// Jets over the K squared lengths q[first .. first + K) (the rest constant), then the chain rule.
template <int K, bool kSecond, int first, int NV, int ND, int NR, class F>
void differentiateIn(const F& f, const std::array<double, ND + NR>& q,
                     const std::array<Eigen::Vector3d, ND + NR>& edgeVectors, const std::array<LocalEdge, ND>& deformedEdges,
                     const std::array<LocalEdge, NR>& referenceEdges, unsigned need, double weight, LocalTerm<NV>& out) {
  constexpr int N = ND + NR;
  std::array<Jet2<K, kSecond>, N> qJet;
  for (int m = 0; m < N; ++m) {
    qJet[m] = (m >= first && m < first + K) ? Jet2<K, kSecond>::variable(q[m], m - first) : Jet2<K, kSecond>(q[m]);
  }
  const Jet2<K, kSecond> r = f(qJet);
  Eigen::Matrix<double, N, 1> g = Eigen::Matrix<double, N, 1>::Zero();
  Eigen::Matrix<double, N, N> H = Eigen::Matrix<double, N, N>::Zero();
  g.template segment<K>(first) = r.g;
  if constexpr (kSecond) H.template block<K, K>(first, first) = r.H;
  chainToPositions<NV, ND, NR>(r.v, g, H, edgeVectors, deformedEdges, referenceEdges, need, weight, out);
}

/// Evaluates f(q_deformed[ND], q_reference[NR]) and chains its derivatives to the NV local vertices,
/// adding weight times the requested outputs to out.
template <int NV, int ND, int NR, class F>
void addSquaredLengthTerm(const F& f, const std::array<Eigen::Vector3d, NV>& deformed,
                          const std::array<Eigen::Vector3d, NV>& reference, const std::array<LocalEdge, ND>& deformedEdges,
                          const std::array<LocalEdge, NR>& referenceEdges, unsigned need, double weight, LocalTerm<NV>& out) {
  constexpr int N = ND + NR;
  std::array<double, N> q;
  std::array<Eigen::Vector3d, N> edgeVectors;
  for (int m = 0; m < N; ++m) {
    const bool isDeformed = m < ND;
    const LocalEdge& edge = isDeformed ? deformedEdges[m] : referenceEdges[m - ND];
    const auto& x = isDeformed ? deformed : reference;
    edgeVectors[m] = x[edge[0]] - x[edge[1]];
    q[m] = edgeVectors[m].squaredNorm();
  }
  if ((need & ~kValue) == 0u) {
    out.value += weight * f(q);
    return;
  }
  // Differentiate only in the squared lengths the requested outputs depend on (the others enter as
  // constants), and to second order only when a Hessian block is requested.
  constexpr unsigned kDeformedOnly = kValue | kGradientDeformed | kHessianDeformed;
  constexpr unsigned kReferenceOnly = kValue | kGradientReference | kHessianReference;
  const bool second = (need & kAnyHessian) != 0u;
  if constexpr (ND > 0) {
    if ((need & ~kDeformedOnly) == 0u) {
      if (second) return differentiateIn<ND, true, 0, NV, ND, NR>(f, q, edgeVectors, deformedEdges, referenceEdges, need, weight, out);
      return differentiateIn<ND, false, 0, NV, ND, NR>(f, q, edgeVectors, deformedEdges, referenceEdges, need, weight, out);
    }
  }
  if constexpr (NR > 0) {
    if ((need & ~kReferenceOnly) == 0u) {
      if (second) return differentiateIn<NR, true, ND, NV, ND, NR>(f, q, edgeVectors, deformedEdges, referenceEdges, need, weight, out);
      return differentiateIn<NR, false, ND, NV, ND, NR>(f, q, edgeVectors, deformedEdges, referenceEdges, need, weight, out);
    }
  }
  if (second) return differentiateIn<N, true, 0, NV, ND, NR>(f, q, edgeVectors, deformedEdges, referenceEdges, need, weight, out);
  differentiateIn<N, false, 0, NV, ND, NR>(f, q, edgeVectors, deformedEdges, referenceEdges, need, weight, out);
}

}  // namespace deformation_enrichment::shape_space::detail
