#pragma once
// Kernel widths (sigma_rho, sigma_u) of eq. (15) by leave-one-out cross-validation over the example set
// ([Seiler14 §5]: "minimizing the cross-validation error against the example data ... simple brute-force").
// For every width pair on a grid and every example k: build the RBF interpolator (rbf_interpolation.hpp)
// from the other examples (or the other sites, see leaveOneOutError), predict k's stamp as sum_i w~_i Psi[i] (eq. 16) from k's eq. (15) weights,
// and sum the squared stamp differences. The error is relative: sum_k |Psi^_k - Psi_k|^2 / sum_k |Psi_k|^2.
// Stamps enter only through their Gram matrix G_ij = <Psi_i, Psi_j>, so a trial costs O(N^3) per held-out
// example regardless of the stamp resolution, and (K_S)^2 = (K^2)_SS - K_Sk K_kS reuses one K^2 per pair.
#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <vector>

#include "deformation_enrichment/enrichment/blending_weights.hpp"
#include "deformation_enrichment/enrichment/rbf_interpolation.hpp"

namespace deformation_enrichment::enrichment {

/// G_ij = sum over nodes and channels of Psi_i Psi_j (double accumulation). Stamps must share size and
/// type CV_32FC3; throws InvalidInputError otherwise.
Eigen::MatrixXd stampGramMatrix(const std::vector<cv::Mat>& stamps);

struct KernelWidthGrid {
  std::vector<double> sigmaRho;
  std::vector<double> sigmaU;
};

/// Geometric grids: sigma_rho over [0.05, 5] x the median non-zero d_rho between examples (1 if all
/// coincide), sigma_u over [0.02, 2] (d_u lies in [0, 2]); `count` values each. A positive `sigmaRhoFloor`
/// makes the sigma_rho grid start there (and span at least a factor 100): site differences below the site
/// descriptor's resolution are sampling noise, and a width at noise level makes the weights follow it.
KernelWidthGrid defaultKernelWidthGrid(const ExampleDissimilarities& d, int count = 12, double sigmaRhoFloor = 0.0);

/// Relative leave-one-out stamp error for one width pair (see above). Needs at least 2 examples and a
/// non-zero stamp; throws InvalidInputError otherwise or for mismatched sizes. With `magnitudes` m_i (|mu[i]|,
/// one per example) the held-out stamp is predicted as the magnitude-aware run time does (contact_enricher.hpp):
/// sum_i w~_i (m_k / m_i) Psi[i]. With `groups` (a group id per example) examples leave in groups: the
/// examples of one site (several patterns at one contact) are predicted from the other sites only, which is
/// what a new contact is; empty: every example alone.
double leaveOneOutError(const ExampleDissimilarities& d, const Eigen::MatrixXd& stampGram, const KernelWidths& widths,
                        double lambda = RbfInterpolator::kDefaultRegularisation,
                        const Eigen::VectorXd& magnitudes = Eigen::VectorXd(), const std::vector<int>& groups = {});

struct KernelWidthFit {
  KernelWidths best;
  double bestError = 0.0;
  /// Cross-validated stamp gain at the best widths: the g in [0, 1] with the least leave-one-out error of
  /// g Psi^_k against Psi_k. Near 1 when the examples predict each other; it falls towards 0 where they do
  /// not, so a set whose examples do not generalise fades its detail instead of adding wrong detail.
  double gain = 1.0;
  double gainedError = 0.0;  ///< the relative leave-one-out error with that gain (<= bestError, <= 1)
  KernelWidthGrid grid;
  Eigen::MatrixXd errors;  ///< errors(a, b) for grid.sigmaRho[a], grid.sigmaU[b]
};

/// Brute force over the grid (OpenMP over width pairs); the minimum of `errors` wins.
KernelWidthFit fitKernelWidths(const ExampleDissimilarities& d, const Eigen::MatrixXd& stampGram, const KernelWidthGrid& grid,
                               double lambda = RbfInterpolator::kDefaultRegularisation,
                               const Eigen::VectorXd& magnitudes = Eigen::VectorXd(), const std::vector<int>& groups = {});

}  // namespace deformation_enrichment::enrichment
