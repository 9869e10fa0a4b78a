#include "deformation_enrichment/enrichment/rbf_interpolation.hpp"

#include <Eigen/Cholesky>
#include <cmath>
#include <string>

#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::enrichment {

ExampleDissimilarities exampleDissimilarities(const ExampleDescriptorTable& table, const std::vector<hermite::MomentList>& rho,
                                              const std::vector<hermite::MomentList>& mu) {
  const Eigen::Index n = table.size();
  if (static_cast<Eigen::Index>(rho.size()) != n || static_cast<Eigen::Index>(mu.size()) != n)
    throw InvalidInputError("exampleDissimilarities: " + std::to_string(rho.size()) + " rho and " + std::to_string(mu.size()) +
                            " mu for a table of " + std::to_string(n) + " examples");
  ExampleDissimilarities d;
  d.dRho.resize(n, n);
  d.dU.resize(n, n);
  Correlation c;
  for (Eigen::Index j = 0; j < n; ++j) {
    correlate(table, rho[static_cast<std::size_t>(j)], mu[static_cast<std::size_t>(j)], KernelWidths{}, c);
    d.dRho.col(j) = c.dRho;
    d.dU.col(j) = c.dU;
  }
  // Both measures are symmetric; average away the rounding of the expanded eq. (9).
  d.dRho = (0.5 * (d.dRho + d.dRho.transpose())).eval();
  d.dU = (0.5 * (d.dU + d.dU.transpose())).eval();
  d.dRho.diagonal().setZero();
  d.dU.diagonal().setZero();
  return d;
}

Eigen::MatrixXd kernelMatrix(const ExampleDissimilarities& d, const KernelWidths& widths) {
  if (d.dRho.rows() != d.dRho.cols() || d.dU.rows() != d.dRho.rows() || d.dU.cols() != d.dRho.cols())
    throw InvalidInputError("kernelMatrix: dissimilarity matrices are not square and equal in size");
  const Eigen::Index n = d.dRho.rows();
  Eigen::MatrixXd K(n, n);
  for (Eigen::Index j = 0; j < n; ++j) K.col(j) = blendingWeights(d.dRho.col(j), d.dU.col(j), widths);  // eq. (15)
  return 0.5 * (K + K.transpose());
}

RbfInterpolator::RbfInterpolator(const Eigen::MatrixXd& K, double lambda) {
  if (K.rows() == 0 || K.rows() != K.cols()) throw InvalidInputError("RbfInterpolator: kernel matrix is empty or not square");
  if (!K.allFinite()) throw InvalidInputError("RbfInterpolator: kernel matrix is not finite");
  if (K.minCoeff() < 0.0 || K.maxCoeff() > 1.0 + 1e-12) throw InvalidInputError("RbfInterpolator: kernel entries outside [0, 1]");
  if (!(lambda > 0.0 && std::isfinite(lambda))) throw InvalidInputError("RbfInterpolator: regularisation must be positive");
  // Normal equations of the Tikhonov problem min |K x - w|^2 + lambda^2 |x|^2: SPD for any symmetric K.
  Eigen::MatrixXd A = K.transpose() * K;
  A.diagonal().array() += lambda * lambda;
  const Eigen::LLT<Eigen::MatrixXd> llt(A);
  if (llt.info() != Eigen::Success) throw NumericalError("RbfInterpolator: regularised kernel system is not positive definite");
  M_ = llt.solve(K.transpose());
  if (!M_.allFinite()) throw NumericalError("RbfInterpolator: interpolation matrix is not finite");
}

void RbfInterpolator::interpolate(const Eigen::VectorXd& w, RbfWeights& out) const {
  if (w.size() != M_.cols())
    throw InvalidInputError("RbfInterpolator::interpolate: " + std::to_string(w.size()) + " weights for " + std::to_string(M_.cols()) +
                            " examples");
  if (!w.allFinite()) throw InvalidInputError("RbfInterpolator::interpolate: weights are not finite");
  if (w.minCoeff() < 0.0 || w.maxCoeff() > 1.0 + 1e-12) throw InvalidInputError("RbfInterpolator::interpolate: weights outside [0, 1]");
  out.weights.resize(M_.rows());
  out.weights.noalias() = M_ * w;
  out.confidence = w.maxCoeff();
}

}  // namespace deformation_enrichment::enrichment
