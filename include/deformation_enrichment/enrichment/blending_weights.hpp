#pragma once
// Example correlation of [Seiler14 §5]: dissimilarities d_rho (eq. 9) and d_u (eq. 14) of the current contact
// against every example, combined into Gaussian-kernel weights (eq. 15)
//   w_i = exp(-d_rho(rho, rho[i])^2 / (2 sigma_rho^2) - d_u(mu, mu[i])^2 / (2 sigma_u^2)).
// The examples are stored contiguously (one column each, components scaled by sqrt(multiplicity) so the
// full-tensor metric is Euclidean, mu pre-normalised), so one call is two dense matrix-vector products per
// block of examples; the blocks of a large table are shared among OpenMP threads, with the same numbers.
#include <Eigen/Core>
#include <vector>

#include "deformation_enrichment/hermite/moment_list.hpp"

namespace deformation_enrichment::enrichment {

struct KernelWidths {
  double sigmaRho = 1.0;
  double sigmaU = 0.8;  ///< [Seiler14 Table 1] uses sigma_mu = 0.8
};

/// Example descriptors (each in its own stamping frame, as stored at acquisition).
class ExampleDescriptorTable {
public:
  /// Throws InvalidInputError for no examples, mismatched counts or layouts, or NaN.
  ExampleDescriptorTable(const std::vector<hermite::MomentList>& rho, const std::vector<hermite::MomentList>& mu);

  Eigen::Index size() const { return rho_.cols(); }
  /// sqrt(multiplicity)-scaled site descriptors, one column per example.
  const Eigen::MatrixXd& rho() const { return rho_; }
  /// sqrt(multiplicity)-scaled, unit-norm deformation descriptors (zero columns for zero mu).
  const Eigen::MatrixXd& muUnit() const { return muUnit_; }
  /// Whether example i has mu = 0 (d_u is then 0 or 1, eq. 14 conventions).
  const Eigen::Array<bool, Eigen::Dynamic, 1>& muZero() const { return muZero_; }
  const hermite::MomentList& rhoLayout() const { return rhoLayout_; }
  const hermite::MomentList& muLayout() const { return muLayout_; }

  /// |rho_i|^2 in the metric (for the expanded form of eq. 9).
  const Eigen::VectorXd& rhoSquaredNorm() const { return rhoSquaredNorm_; }
  /// sqrt(multiplicity) per component, for scaling a query.
  const Eigen::VectorXd& rhoMetric() const { return rhoMetric_; }
  const Eigen::VectorXd& muMetric() const { return muMetric_; }

private:
  Eigen::MatrixXd rho_, muUnit_;
  Eigen::VectorXd rhoSquaredNorm_, rhoMetric_, muMetric_;
  Eigen::Array<bool, Eigen::Dynamic, 1> muZero_;
  hermite::MomentList rhoLayout_, muLayout_;
};

struct Correlation {
  Eigen::VectorXd dRho;     ///< eq. (9) per example
  Eigen::VectorXd dU;       ///< eq. (14) per example
  Eigen::VectorXd weights;  ///< eq. (15) per example
};

/// d_rho, d_u and the eq. (15) weights of the current descriptors against all examples. `out` is reused
/// across calls (no allocation once sized). Throws InvalidInputError for layouts that differ from the
/// table's, NaN, or non-positive kernel widths.
void correlate(const ExampleDescriptorTable& examples, const hermite::MomentList& rho,
               const hermite::MomentList& mu, const KernelWidths& widths, Correlation& out);

/// eq. (15) from given dissimilarities (same sizes).
Eigen::VectorXd blendingWeights(const Eigen::VectorXd& dRho, const Eigen::VectorXd& dU, const KernelWidths& widths);

}  // namespace deformation_enrichment::enrichment
