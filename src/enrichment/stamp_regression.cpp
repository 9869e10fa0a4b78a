#include "deformation_enrichment/enrichment/stamp_regression.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <string>

#include "deformation_enrichment/enrichment/rbf_interpolation.hpp"
#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::enrichment {
namespace {

// The grid: sigma_rho as multiples of the median non-zero d_rho between examples, epsilon geometric.
constexpr double kSigmaFactors[] = {0.1, 0.3, 1.0, 3.0, 10.0};
constexpr double kEpsilons[] = {1e-3, 1e-2, 3e-2, 0.1, 0.3, 1.0};

double medianOffDiagonal(const Eigen::MatrixXd& d) {
  std::vector<double> values;
  for (Eigen::Index j = 0; j < d.cols(); ++j)
    for (Eigen::Index i = 0; i < j; ++i)
      if (d(i, j) > 0.0) values.push_back(d(i, j));
  if (values.empty()) return 1.0;  // all sites coincide: any width
  std::nth_element(values.begin(), values.begin() + static_cast<long>(values.size() / 2), values.end());
  return values[values.size() / 2];
}

Eigen::MatrixXd kernel(const Eigen::MatrixXd& dRho, const Eigen::MatrixXd& linear, double sigmaRho) {
  return ((-0.5 / (sigmaRho * sigmaRho)) * dRho.array().square()).exp().matrix().cwiseProduct(linear);
}

// Leave-one-out of A = K + lambda I with the stamps' Gram G: residual r_i = [A^-1 Y]_i / [A^-1]_ii, so
// |r_i|^2 = [A^-1 G A^-1]_ii / [A^-1]_ii^2 and <Y_i, r_i> = [G A^-1]_ii / [A^-1]_ii.
StampRegressionFit looFit(const Eigen::MatrixXd& inverse, const Eigen::MatrixXd& G) {
  const Eigen::MatrixXd GA = G * inverse;
  const Eigen::MatrixXd AGA = inverse * GA;
  double residual = 0.0, signal = 0.0, cross = 0.0, predicted = 0.0;
  for (Eigen::Index i = 0; i < G.rows(); ++i) {
    const double a = inverse(i, i);
    const double rr = AGA(i, i) / (a * a), yr = GA(i, i) / a;
    residual += rr;
    signal += G(i, i);
    cross += G(i, i) - yr;                 // <Y_i, Y^_i>, Y^_i = Y_i - r_i
    predicted += G(i, i) - 2.0 * yr + rr;  // |Y^_i|^2
  }
  StampRegressionFit fit;
  fit.looError = residual / signal;
  fit.gain = predicted > 0.0 ? std::clamp(cross / predicted, 0.0, 1.0) : 0.0;
  fit.gainedError = (signal - 2.0 * fit.gain * cross + fit.gain * fit.gain * predicted) / signal;
  return fit;
}

}  // namespace

StampRegression::StampRegression(const std::vector<hermite::MomentList>& rho, const std::vector<hermite::MomentList>& mu,
                                 const Eigen::MatrixXd& stampGram) {
  if (rho.size() < 2) throw InvalidInputError("stamp regression: needs at least 2 examples, got " + std::to_string(rho.size()));
  const Eigen::Index n = static_cast<Eigen::Index>(rho.size());
  if (stampGram.rows() != n || stampGram.cols() != n)
    throw InvalidInputError("stamp regression: the stamp Gram matrix is not " + std::to_string(n) + " x " + std::to_string(n));
  if (!(stampGram.trace() > 0.0)) throw InvalidInputError("stamp regression: every stamp is zero");
  table_ = std::make_unique<ExampleDescriptorTable>(rho, mu);  // checks counts, layouts and finiteness
  mu_.resize(table_->muMetric().size(), n);
  for (Eigen::Index i = 0; i < n; ++i) mu_.col(i) = table_->muMetric().cwiseProduct(mu[static_cast<std::size_t>(i)].values());
  const Eigen::MatrixXd dRho = exampleDissimilarities(*table_, rho, mu).dRho;
  const Eigen::MatrixXd linear = mu_.transpose() * mu_;
  const double scale = medianOffDiagonal(dRho);
  bool any = false;
  for (const double factor : kSigmaFactors) {
    const Eigen::MatrixXd K = kernel(dRho, linear, factor * scale);
    const double meanDiagonal = K.diagonal().mean();
    if (!(meanDiagonal > 0.0)) continue;  // every mu zero
    for (const double epsilon : kEpsilons) {
      Eigen::MatrixXd A = K;
      A.diagonal().array() += epsilon * meanDiagonal;
      const Eigen::LDLT<Eigen::MatrixXd> ldlt(A);
      if (ldlt.info() != Eigen::Success || !ldlt.isPositive()) continue;
      const Eigen::MatrixXd inverse = ldlt.solve(Eigen::MatrixXd::Identity(n, n));
      StampRegressionFit trial = looFit(inverse, stampGram);
      if (!std::isfinite(trial.looError) || (any && trial.looError >= fit_.looError)) continue;
      trial.sigmaRho = factor * scale;
      trial.epsilon = epsilon;
      fit_ = trial;
      weightsMatrix_ = inverse;
      any = true;
    }
  }
  if (!any) throw InvalidInputError("stamp regression: no example deforms (every mu is zero) or no kernel matrix factorises");
}

void StampRegression::weights(const hermite::MomentList& rho, const hermite::MomentList& mu, Eigen::VectorXd& weights,
                              double& confidence) const {
  correlate(*table_, rho, mu, KernelWidths{fit_.sigmaRho, 1.0}, correlation_);  // d_rho (eq. 9); checks layouts and NaN
  const Eigen::VectorXd scaledMu = table_->muMetric().cwiseProduct(mu.values());
  k_ = ((-0.5 / (fit_.sigmaRho * fit_.sigmaRho)) * correlation_.dRho.array().square()).exp().matrix().cwiseProduct(mu_.transpose() * scaledMu);
  weights.noalias() = weightsMatrix_ * k_;
  const double prior = scaledMu.squaredNorm();
  confidence = prior > 0.0 ? std::clamp(k_.dot(weights) / prior, 0.0, 1.0) : 0.0;
}

}  // namespace deformation_enrichment::enrichment
