#pragma once
// Forward-mode automatic differentiation over a handful of variables: value and gradient, and (when
// kSecond) the Hessian carried along. Used for the shell energies written as functions of squared edge
// lengths, where N <= 6 keeps the N x N Hessian per operation cheap; the first-order variant serves the
// gradient-only evaluations. Private to the shape_space module.
#include <cmath>

#include <Eigen/Core>

namespace deformation_enrichment::shape_space::detail {

template <int N, bool kSecond = true>
struct Jet2 {
  static constexpr int M = kSecond ? N : 0;  // Hessian size (empty for first order)
  using Vector = Eigen::Matrix<double, N, 1>;
  using Matrix = Eigen::Matrix<double, M, M>;
  double v = 0.0;
  Vector g = Vector::Zero();
  Matrix H = Matrix::Zero();

  Jet2() = default;
  Jet2(double value) : v(value) {}  // NOLINT: constants mix freely with variables
  static Jet2 variable(double value, int index) {
    Jet2 j(value);
    j.g[index] = 1.0;
    return j;
  }
};

// phi(a) with phi' = d1, phi'' = d2 at a.v (chain rule to second order).
template <int N, bool S>
Jet2<N, S> applyUnary(const Jet2<N, S>& a, double value, double d1, double d2) {
  Jet2<N, S> r;
  r.v = value;
  r.g = d1 * a.g;
  if constexpr (S) r.H = d1 * a.H + d2 * a.g * a.g.transpose();
  return r;
}

template <int N, bool S>
Jet2<N, S> operator+(const Jet2<N, S>& a, const Jet2<N, S>& b) {
  Jet2<N, S> r;
  r.v = a.v + b.v;
  r.g = a.g + b.g;
  if constexpr (S) r.H = a.H + b.H;
  return r;
}
template <int N, bool S>
Jet2<N, S> operator-(const Jet2<N, S>& a, const Jet2<N, S>& b) {
  Jet2<N, S> r;
  r.v = a.v - b.v;
  r.g = a.g - b.g;
  if constexpr (S) r.H = a.H - b.H;
  return r;
}
template <int N, bool S>
Jet2<N, S> operator-(const Jet2<N, S>& a) {
  Jet2<N, S> r;
  r.v = -a.v;
  r.g = -a.g;
  if constexpr (S) r.H = -a.H;
  return r;
}
template <int N, bool S>
Jet2<N, S> operator*(const Jet2<N, S>& a, const Jet2<N, S>& b) {
  Jet2<N, S> r;
  r.v = a.v * b.v;
  r.g = a.v * b.g + b.v * a.g;
  if constexpr (S) {
    const Eigen::Matrix<double, N, N> outer = a.g * b.g.transpose();
    r.H = a.v * b.H + b.v * a.H + outer + outer.transpose();
  }
  return r;
}
template <int N, bool S>
Jet2<N, S> operator*(double s, const Jet2<N, S>& a) {
  Jet2<N, S> r;
  r.v = s * a.v;
  r.g = s * a.g;
  if constexpr (S) r.H = s * a.H;
  return r;
}
template <int N, bool S>
Jet2<N, S> operator*(const Jet2<N, S>& a, double s) {
  return s * a;
}
template <int N, bool S>
Jet2<N, S> operator+(const Jet2<N, S>& a, double s) {
  Jet2<N, S> r = a;
  r.v += s;
  return r;
}
template <int N, bool S>
Jet2<N, S> operator+(double s, const Jet2<N, S>& a) {
  return a + s;
}
template <int N, bool S>
Jet2<N, S> operator-(const Jet2<N, S>& a, double s) {
  return a + (-s);
}
template <int N, bool S>
Jet2<N, S> operator-(double s, const Jet2<N, S>& a) {
  return (-a) + s;
}
template <int N, bool S>
Jet2<N, S> reciprocal(const Jet2<N, S>& a) {
  const double inv = 1.0 / a.v;
  return applyUnary(a, inv, -inv * inv, 2.0 * inv * inv * inv);
}
template <int N, bool S>
Jet2<N, S> operator/(const Jet2<N, S>& a, const Jet2<N, S>& b) {
  return a * reciprocal(b);
}
template <int N, bool S>
Jet2<N, S> operator/(const Jet2<N, S>& a, double s) {
  return (1.0 / s) * a;
}
template <int N, bool S>
Jet2<N, S> operator/(double s, const Jet2<N, S>& a) {
  return s * reciprocal(a);
}
template <int N, bool S>
Jet2<N, S> sqrt(const Jet2<N, S>& a) {
  const double root = std::sqrt(a.v);
  return applyUnary(a, root, 0.5 / root, -0.25 / (root * a.v));
}
template <int N, bool S>
Jet2<N, S> log(const Jet2<N, S>& a) {
  return applyUnary(a, std::log(a.v), 1.0 / a.v, -1.0 / (a.v * a.v));
}

inline double valueOf(double a) { return a; }
template <int N, bool S>
double valueOf(const Jet2<N, S>& a) {
  return a.v;
}

}  // namespace deformation_enrichment::shape_space::detail
