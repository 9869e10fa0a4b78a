#pragma once
// Shared fixtures of the descriptor tests: meshes, random rigid motions and the closed-form density moments
// of an axis-aligned box (the reference for quadrature accuracy).
#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "deformation_enrichment/hermite/moment_list.hpp"
#include "deformation_enrichment/hermite/multi_index.hpp"
#include "deformation_enrichment/mesh/grid_tet_mesh.hpp"

namespace de_test {

using namespace deformation_enrichment;

inline Eigen::Matrix3d randomRotation(std::mt19937& rng) {
  std::normal_distribution<double> normal;
  return Eigen::Quaterniond(normal(rng), normal(rng), normal(rng), normal(rng)).normalized().toRotationMatrix();
}

inline mesh::TetMesh uniformBox(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, int cellsPerUnit) {
  const Eigen::Vector3d extent = hi - lo;
  const Eigen::Vector3i cells((extent * cellsPerUnit).array().round().cast<int>().max(1).matrix());
  return mesh::gridTetMesh(lo, hi, cells);
}

// int_a^b phi(s) He_k(s) ds with phi the unit normal density: Phi(b) - Phi(a) for k = 0, and
// -[phi He_{k-1}]_a^b for k >= 1 (because (phi He_{k-1})' = -phi He_k). Closed form, no quadrature.
inline double gaussianHermiteIntegral(int k, double a, double b) {
  auto phi = [](double s) { return std::exp(-0.5 * s * s) / std::sqrt(2.0 * M_PI); };
  auto he = [](int n, double s) {
    double previous = 1.0, current = s;
    if (n == 0) return previous;
    for (int j = 1; j < n; ++j) {
      const double next = s * current - j * previous;
      previous = current;
      current = next;
    }
    return current;
  };
  if (k == 0) return 0.5 * (std::erf(b / std::sqrt(2.0)) - std::erf(a / std::sqrt(2.0)));
  return -(phi(b) * he(k - 1, b) - phi(a) * he(k - 1, a));
}

// Exact density moments (eq. 7) of the box [lo, hi] around p with scale h: the integrand separates per axis.
inline hermite::MomentList boxMoments(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                                      const Eigen::Vector3d& p, double h, int order) {
  hermite::MomentList moments(0, order, 1);
  for (int n = 0; n <= order; ++n) {
    const auto& alphas = hermite::multiIndices(n);
    for (std::size_t c = 0; c < alphas.size(); ++c) {
      double value = 1.0 / std::sqrt(hermite::factorial(n));
      for (int axis = 0; axis < 3; ++axis)
        value *= gaussianHermiteIntegral(alphas[c][axis], (lo[axis] - p[axis]) / h, (hi[axis] - p[axis]) / h);
      moments.order(n)[c] = value;
    }
  }
  return moments;
}

inline double relativeError(const hermite::MomentList& a, const hermite::MomentList& reference) {
  hermite::MomentList difference = a;
  difference.values() -= reference.values();
  return hermite::norm(difference) / hermite::norm(reference);
}

}  // namespace de_test
