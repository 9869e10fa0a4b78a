#pragma once
// Finiteness of a whole state buffer in one vectorised pass: x * 0 is NaN exactly for non-finite x, and a sum
// over the flat buffer runs in SIMD lanes, where Eigen's allFinite on a 3 x n matrix goes element by element
// (5 % of a 50k-vertex frame, bench_session).
#include <Eigen/Core>
#include <cmath>

namespace deformation_enrichment {

/// Whether every value of a contiguous matrix (outer stride = rows) is finite.
template <typename Derived>
bool allFiniteValues(const Eigen::DenseBase<Derived>& values) {
  using Scalar = typename Derived::Scalar;
  const auto& m = values.derived();
  const Eigen::Map<const Eigen::Array<Scalar, Eigen::Dynamic, 1>> flat(m.data(), m.size());
  return std::isfinite((flat * Scalar(0)).sum());
}

}  // namespace deformation_enrichment
