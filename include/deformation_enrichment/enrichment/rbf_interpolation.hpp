#pragma once
// RBF interpolation of the example weights ([Seiler14 §5], following [Seiler14b]). The eq. (15) Gaussian
// weights w(q) of a query q against the N examples are turned into interpolating weights
//   w~ = (K^2 + lambda^2 I)^-1 K w,   K_ij = w_j(example i)  (the examples' kernel matrix),
// the Tikhonov-regularised solution of K w~ = w. Without regularisation, a query equal to example i has
// w = K e_i and gets w~ = e_i (interpolation). lambda > 0 keeps the system solvable when two examples
// coincide (K then has two equal rows; their weight is split evenly) and is needed because the d_u
// kernel (1 - cosine, squared) is not positive definite, so K + lambda I alone could be singular.
// The map w -> w~ is linear, so w~ -> 0 as every w_i -> 0: detail fades out where no example is similar.
// The confidence max_i w_i in [0, 1] reports how similar the nearest example is.
#include <Eigen/Core>
#include <vector>

#include "deformation_enrichment/enrichment/blending_weights.hpp"
#include "deformation_enrichment/hermite/moment_list.hpp"

namespace deformation_enrichment::enrichment {

/// Pairwise dissimilarities of the examples: column j holds d_rho (eq. 9) and d_u (eq. 14) of example j's
/// descriptors against every example (symmetric, zero diagonal).
struct ExampleDissimilarities {
  Eigen::MatrixXd dRho;
  Eigen::MatrixXd dU;
};

/// Computes them with correlate() (the table's own eq. 9 / 14). rho, mu: the descriptors the table was
/// built from. Throws InvalidInputError for mismatched counts.
ExampleDissimilarities exampleDissimilarities(const ExampleDescriptorTable& table, const std::vector<hermite::MomentList>& rho,
                                              const std::vector<hermite::MomentList>& mu);

/// K_ij = eq. (15) weight between examples i and j (symmetrised).
Eigen::MatrixXd kernelMatrix(const ExampleDissimilarities& d, const KernelWidths& widths);

struct RbfWeights {
  Eigen::VectorXd weights;  ///< w~, the eq. (16) blending weights
  double confidence = 0.0;  ///< max_i w_i in [0, 1]
};

class RbfInterpolator {
public:
  static constexpr double kDefaultRegularisation = 1e-3;

  /// K: the examples' kernel matrix (square, finite, entries in [0, 1]); lambda > 0. Throws
  /// InvalidInputError otherwise, NumericalError if the regularised system cannot be factorised.
  explicit RbfInterpolator(const Eigen::MatrixXd& K, double lambda = kDefaultRegularisation);

  Eigen::Index size() const { return M_.rows(); }
  /// w~ = M w with M = (K^2 + lambda^2 I)^-1 K precomputed (one matrix-vector product per query).
  const Eigen::MatrixXd& interpolationMatrix() const { return M_; }

  /// w~ and the confidence for the eq. (15) weights w of a query. `out` is reused (no allocation once
  /// sized). Throws InvalidInputError for a wrong size, NaN, or weights outside [0, 1].
  void interpolate(const Eigen::VectorXd& w, RbfWeights& out) const;

private:
  Eigen::MatrixXd M_;
};

}  // namespace deformation_enrichment::enrichment
