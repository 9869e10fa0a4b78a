#include "deformation_enrichment/enrichment/kernel_width_fitting.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <string>

#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::enrichment {

namespace {

void checkInputs(const ExampleDissimilarities& d, const Eigen::MatrixXd& G) {
  const Eigen::Index n = d.dRho.rows();
  if (n < 2) throw InvalidInputError("kernel width fitting: leave-one-out needs at least 2 examples");
  if (d.dRho.cols() != n || d.dU.rows() != n || d.dU.cols() != n || G.rows() != n || G.cols() != n)
    throw InvalidInputError("kernel width fitting: dissimilarity and Gram matrices differ in size");
  if (!d.dRho.allFinite() || !d.dU.allFinite() || !G.allFinite()) throw InvalidInputError("kernel width fitting: NaN input");
  if (!(G.trace() > 0.0)) throw InvalidInputError("kernel width fitting: every stamp is zero, nothing to predict");
}

std::vector<double> geometric(double lo, double hi, int count) {
  std::vector<double> v(static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i) v[static_cast<std::size_t>(i)] = count == 1 ? lo : lo * std::pow(hi / lo, double(i) / (count - 1));
  return v;
}

// Sums over the held-out examples k of <Psi^_k, Psi_k>, |Psi^_k|^2 and |Psi_k|^2, each weighted by c_k (1
// when `scale` is empty, else scale_k). Examples leave in groups (`groups`: a group id per example, empty:
// every example alone): Psi^_k = sum_{i in S} x_i Psi_i over the others S, with
// x = ((K_S)^2 + lambda^2 I)^-1 K_S K_Sk (the RBF weights of rbf_interpolation.hpp from S); G is the Gram
// matrix of the Psi.
struct LeaveOneOutSums {
  double cross = 0.0, predicted = 0.0, truth = 0.0;
  double squaredError() const { return std::max(0.0, predicted - 2.0 * cross + truth); }
  /// The gain g in [0, 1] minimising sum_k |g Psi^_k - Psi_k|^2.
  double gain() const { return predicted > 0.0 ? std::clamp(cross / predicted, 0.0, 1.0) : 0.0; }
};

LeaveOneOutSums leaveOneOutSums(const Eigen::MatrixXd& K, const Eigen::MatrixXd& G, double lambda, const Eigen::VectorXd& scale,
                                const std::vector<int>& groups) {
  const Eigen::Index n = K.rows();
  const Eigen::MatrixXd K2 = K * K;
  std::vector<int> group(groups);
  if (group.empty())
    for (Eigen::Index i = 0; i < n; ++i) group.push_back(static_cast<int>(i));
  std::vector<int> ids(group);
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  LeaveOneOutSums sums;
  std::vector<Eigen::Index> others, held;
  Eigen::LLT<Eigen::MatrixXd> llt;
  for (const int id : ids) {
    others.clear();
    held.clear();
    for (Eigen::Index i = 0; i < n; ++i) (group[static_cast<std::size_t>(i)] == id ? held : others).push_back(i);
    if (others.empty()) throw InvalidInputError("kernel width fitting: leaving a group out leaves no example");
    // (K_S)^2 = (K^2)_SS - K_SH K_HS: the held-out rows' contribution removed from the full square.
    const Eigen::MatrixXd kSH = K(others, held);
    Eigen::MatrixXd A = K2(others, others);
    A.noalias() -= kSH * kSH.transpose();
    A.diagonal().array() += lambda * lambda;
    llt.compute(A);
    if (llt.info() != Eigen::Success) throw NumericalError("kernel width fitting: regularised system not positive definite");
    const Eigen::MatrixXd X = llt.solve(K(others, others) * kSH);  // one column of RBF weights per held-out example
    for (std::size_t h = 0; h < held.size(); ++h) {
      const Eigen::Index k = held[h];
      const Eigen::VectorXd x = X.col(static_cast<Eigen::Index>(h));
      const double s = scale.size() ? scale[k] : 1.0;
      sums.predicted += s * x.dot(G(others, others) * x);
      sums.cross += s * x.dot(G(others, k));
      sums.truth += s * G(k, k);
    }
  }
  return sums;
}

}  // namespace

Eigen::MatrixXd stampGramMatrix(const std::vector<cv::Mat>& stamps) {
  if (stamps.empty()) throw InvalidInputError("stampGramMatrix: no stamps");
  const Eigen::Index n = static_cast<Eigen::Index>(stamps.size());
  for (std::size_t i = 0; i < stamps.size(); ++i) {
    if (stamps[i].type() != CV_32FC3) throw InvalidInputError("stampGramMatrix: stamp " + std::to_string(i) + " is not CV_32FC3");
    if (stamps[i].size() != stamps[0].size()) throw InvalidInputError("stampGramMatrix: stamp " + std::to_string(i) + " differs in size");
  }
  const Eigen::Index values = static_cast<Eigen::Index>(stamps[0].total()) * 3;
  Eigen::MatrixXd flat(values, n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const cv::Mat s = stamps[static_cast<std::size_t>(i)].isContinuous() ? stamps[static_cast<std::size_t>(i)]
                                                                         : stamps[static_cast<std::size_t>(i)].clone();
    flat.col(i) = Eigen::Map<const Eigen::VectorXf>(s.ptr<float>(), values).cast<double>();
  }
  if (!flat.allFinite()) throw InvalidInputError("stampGramMatrix: a stamp contains NaN or Inf");
  return flat.transpose() * flat;
}

KernelWidthGrid defaultKernelWidthGrid(const ExampleDissimilarities& d, int count, double sigmaRhoFloor) {
  if (count < 1) throw InvalidInputError("defaultKernelWidthGrid: count must be positive");
  if (!(sigmaRhoFloor >= 0.0) || !std::isfinite(sigmaRhoFloor))
    throw InvalidInputError("defaultKernelWidthGrid: the sigma_rho floor must be >= 0 and finite");
  std::vector<double> offDiagonal;
  for (Eigen::Index j = 0; j < d.dRho.cols(); ++j)
    for (Eigen::Index i = 0; i < j; ++i)
      if (d.dRho(i, j) > 0.0 && std::isfinite(d.dRho(i, j))) offDiagonal.push_back(d.dRho(i, j));
  double median = 1.0;
  if (!offDiagonal.empty()) {
    std::nth_element(offDiagonal.begin(), offDiagonal.begin() + static_cast<long>(offDiagonal.size() / 2), offDiagonal.end());
    median = offDiagonal[offDiagonal.size() / 2];
  }
  const double lo = std::max(0.05 * median, sigmaRhoFloor);
  return {geometric(lo, std::max(5.0 * median, 100.0 * lo), count), geometric(0.02, 2.0, count)};
}

// Magnitude-aware prediction Psi^_k = sum_i x_i (m_k / m_i) Psi_i: with Phi_i = Psi_i / m_i its error is
// m_k^2 |sum_i x_i Phi_i - Phi_k|^2, the plain error on the Gram matrix of the Phi scaled by m_k^2 (m_i = 0:
// Phi_i = 0, as the run time drops such an example).
struct ScaledGram {
  Eigen::MatrixXd gram;
  Eigen::VectorXd scale;
};
ScaledGram scaledGram(const Eigen::MatrixXd& G, const Eigen::VectorXd& magnitudes) {
  if (magnitudes.size() == 0) return {G, Eigen::VectorXd()};
  if (magnitudes.size() != G.rows() || !magnitudes.allFinite() || (magnitudes.array() < 0.0).any())
    throw InvalidInputError("kernel width fitting: one finite, non-negative magnitude per example expected");
  const Eigen::VectorXd inverse = magnitudes.unaryExpr([](double m) { return m > 0.0 ? 1.0 / m : 0.0; });
  return {inverse.asDiagonal() * G * inverse.asDiagonal(), magnitudes.array().square()};
}

double leaveOneOutError(const ExampleDissimilarities& d, const Eigen::MatrixXd& stampGram, const KernelWidths& widths, double lambda,
                        const Eigen::VectorXd& magnitudes, const std::vector<int>& groups) {
  checkInputs(d, stampGram);
  if (!(lambda > 0.0)) throw InvalidInputError("leaveOneOutError: regularisation must be positive");
  const ScaledGram scaled = scaledGram(stampGram, magnitudes);
  return leaveOneOutSums(kernelMatrix(d, widths), scaled.gram, lambda, scaled.scale, groups).squaredError() / stampGram.trace();
}

KernelWidthFit fitKernelWidths(const ExampleDissimilarities& d, const Eigen::MatrixXd& stampGram, const KernelWidthGrid& grid, double lambda,
                               const Eigen::VectorXd& magnitudes, const std::vector<int>& groups) {
  checkInputs(d, stampGram);
  const ScaledGram scaled = scaledGram(stampGram, magnitudes);
  if (grid.sigmaRho.empty() || grid.sigmaU.empty()) throw InvalidInputError("fitKernelWidths: empty grid");
  for (double s : grid.sigmaRho)
    if (!(s > 0.0 && std::isfinite(s))) throw InvalidInputError("fitKernelWidths: sigma_rho grid values must be positive");
  for (double s : grid.sigmaU)
    if (!(s > 0.0 && std::isfinite(s))) throw InvalidInputError("fitKernelWidths: sigma_u grid values must be positive");
  if (!(lambda > 0.0)) throw InvalidInputError("fitKernelWidths: regularisation must be positive");

  KernelWidthFit fit;
  fit.grid = grid;
  const int a = static_cast<int>(grid.sigmaRho.size()), b = static_cast<int>(grid.sigmaU.size());
  fit.errors.resize(a, b);
  const double norm = stampGram.trace();
  bool failed = false;
#pragma omp parallel for schedule(dynamic)
  for (int pair = 0; pair < a * b; ++pair) {
    const KernelWidths widths{grid.sigmaRho[static_cast<std::size_t>(pair / b)], grid.sigmaU[static_cast<std::size_t>(pair % b)]};
    try {
      fit.errors(pair / b, pair % b) = leaveOneOutSums(kernelMatrix(d, widths), scaled.gram, lambda, scaled.scale, groups).squaredError() / norm;
    } catch (const Error&) {
#pragma omp critical
      failed = true;
    }
  }
  if (failed) throw NumericalError("fitKernelWidths: a leave-one-out system could not be solved");
  Eigen::Index bestA = 0, bestB = 0;
  fit.bestError = fit.errors.minCoeff(&bestA, &bestB);
  fit.best = KernelWidths{grid.sigmaRho[static_cast<std::size_t>(bestA)], grid.sigmaU[static_cast<std::size_t>(bestB)]};
  const LeaveOneOutSums sums = leaveOneOutSums(kernelMatrix(d, fit.best), scaled.gram, lambda, scaled.scale, groups);
  fit.gain = sums.gain();
  fit.gainedError = std::max(0.0, sums.truth - fit.gain * (2.0 * sums.cross - fit.gain * sums.predicted)) / norm;
  return fit;
}

}  // namespace deformation_enrichment::enrichment
