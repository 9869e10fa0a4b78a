#pragma once
// Stamp regression: the blended stamp as the posterior mean of a Gaussian process over descriptors
// ([Rasmussen06 eq. 2.23], kernel ridge regression), in place of the paper's eq. (15) weights + RBF:
//   Psi(x) = sum_i w_i(x) Psi[i],   w(x) = (K + lambda I)^-1 k(x),
//   k(x, x') = exp(-d_rho(rho, rho')^2 / (2 sigma_rho^2)) <mu, mu'>,
// d_rho of eq. (9) and <.,.> the full-tensor dot of eq. (13). The second factor is linear in mu: where the
// site is the same, fine - coarse follows the coarse deformation linearly (as both solves do at small
// strain), so one example covers every depth and the press and drag examples of a site combine, and
// mu = 0 gives no detail. The paper's weights see only the direction of mu (d_u) and interpolate whole
// stamps, and on random held-out contacts they did not improve with more examples (docs/accuracy.md).
// sigma_rho and the ridge lambda = epsilon mean(diag K) are chosen on a grid by the closed-form
// leave-one-out error of the stamps [Rasmussen06 eq. 5.12]: r_i = [A^-1 Y]_i / [A^-1]_ii, A = K + lambda I,
// which needs only the stamps' Gram matrix. The confidence k^T A^-1 k / k(x, x) in [0, 1) is the fraction of
// the prior variance the examples explain ([Rasmussen06 eq. 2.26]): 0 far from every example.
#include <Eigen/Core>
#include <memory>
#include <opencv2/core.hpp>
#include <vector>

#include "deformation_enrichment/enrichment/blending_weights.hpp"
#include "deformation_enrichment/hermite/moment_list.hpp"

namespace deformation_enrichment::enrichment {

struct StampRegressionFit {
  double sigmaRho = 0.0;
  double epsilon = 0.0;        ///< lambda / mean(diag K)
  double looError = 0.0;       ///< relative leave-one-out stamp error at the chosen pair
  /// The g in [0, 1] with the least leave-one-out error of g Psi^_k against Psi_k (KernelWidthFit::gain).
  double gain = 1.0;
  double gainedError = 0.0;
};

class StampRegression {
public:
  /// Fits on the examples' descriptors (each in its frame) and their stamps' Gram matrix. Needs at least
  /// 2 examples (leave-one-out) and a non-zero stamp; throws InvalidInputError otherwise or for layouts
  /// that differ, NaN, or sizes that do not match.
  StampRegression(const std::vector<hermite::MomentList>& rho, const std::vector<hermite::MomentList>& mu,
                  const Eigen::MatrixXd& stampGram);

  const StampRegressionFit& fit() const { return fit_; }
  Eigen::Index size() const { return weightsMatrix_.rows(); }

  /// w(x) and the confidence for descriptors in the current frame. `weights` is reused.
  void weights(const hermite::MomentList& rho, const hermite::MomentList& mu, Eigen::VectorXd& weights, double& confidence) const;

private:
  std::unique_ptr<ExampleDescriptorTable> table_;  // rho for eq. (9)
  Eigen::MatrixXd mu_;                             // sqrt(multiplicity)-scaled mu, one column per example
  Eigen::MatrixXd weightsMatrix_;                  // A^-1
  StampRegressionFit fit_;
  mutable Correlation correlation_;                // scratch for d_rho
  mutable Eigen::VectorXd k_;
};

}  // namespace deformation_enrichment::enrichment
