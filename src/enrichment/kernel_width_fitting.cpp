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

// Sum over held-out k of c_k |Psi^_k - Psi_k|^2 with Psi^_k = sum_{i != k} x_i Psi_i and
// x = ((K_S)^2 + lambda^2 I)^-1 K_S K_Sk (the RBF weights of rbf_interpolation.hpp from the other examples);
// G is the Gram matrix of the Psi, c_k = 1 when `scale` is empty, else scale_k.
double leaveOneOutSquaredError(const Eigen::MatrixXd& K, const Eigen::MatrixXd& G, double lambda, const Eigen::VectorXd& scale) {
  const Eigen::Index n = K.rows();
  const Eigen::MatrixXd K2 = K * K;
  std::vector<Eigen::Index> others(static_cast<std::size_t>(n - 1));
  Eigen::MatrixXd A(n - 1, n - 1);
  Eigen::VectorXd kS(n - 1), rhs(n - 1), x(n - 1), gS(n - 1);
  Eigen::LLT<Eigen::MatrixXd> llt(n - 1);
  double total = 0.0;
  for (Eigen::Index k = 0; k < n; ++k) {
    for (Eigen::Index i = 0, s = 0; i < n; ++i)
      if (i != k) others[static_cast<std::size_t>(s++)] = i;
    kS = K(others, k);
    // (K_S)^2 = (K^2)_SS - K_Sk K_kS: the held-out row's contribution removed from the full square.
    A = K2(others, others);
    A.noalias() -= kS * kS.transpose();
    A.diagonal().array() += lambda * lambda;
    llt.compute(A);
    if (llt.info() != Eigen::Success) throw NumericalError("kernel width fitting: regularised system not positive definite");
    rhs.noalias() = K(others, others) * kS;
    x = llt.solve(rhs);
    gS = G(others, k);
    const double error = x.dot(G(others, others) * x) - 2.0 * x.dot(gS) + G(k, k);
    total += (scale.size() ? scale[k] : 1.0) * std::max(0.0, error);  // a squared norm; clamp the rounding
  }
  return total;
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

KernelWidthGrid defaultKernelWidthGrid(const ExampleDissimilarities& d, int count) {
  if (count < 1) throw InvalidInputError("defaultKernelWidthGrid: count must be positive");
  std::vector<double> offDiagonal;
  for (Eigen::Index j = 0; j < d.dRho.cols(); ++j)
    for (Eigen::Index i = 0; i < j; ++i)
      if (d.dRho(i, j) > 0.0 && std::isfinite(d.dRho(i, j))) offDiagonal.push_back(d.dRho(i, j));
  double median = 1.0;
  if (!offDiagonal.empty()) {
    std::nth_element(offDiagonal.begin(), offDiagonal.begin() + static_cast<long>(offDiagonal.size() / 2), offDiagonal.end());
    median = offDiagonal[offDiagonal.size() / 2];
  }
  return {geometric(0.05 * median, 5.0 * median, count), geometric(0.02, 2.0, count)};
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
                        const Eigen::VectorXd& magnitudes) {
  checkInputs(d, stampGram);
  if (!(lambda > 0.0)) throw InvalidInputError("leaveOneOutError: regularisation must be positive");
  const ScaledGram scaled = scaledGram(stampGram, magnitudes);
  return leaveOneOutSquaredError(kernelMatrix(d, widths), scaled.gram, lambda, scaled.scale) / stampGram.trace();
}

KernelWidthFit fitKernelWidths(const ExampleDissimilarities& d, const Eigen::MatrixXd& stampGram, const KernelWidthGrid& grid, double lambda,
                               const Eigen::VectorXd& magnitudes) {
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
      fit.errors(pair / b, pair % b) = leaveOneOutSquaredError(kernelMatrix(d, widths), scaled.gram, lambda, scaled.scale) / norm;
    } catch (const Error&) {
#pragma omp critical
      failed = true;
    }
  }
  if (failed) throw NumericalError("fitKernelWidths: a leave-one-out system could not be solved");
  Eigen::Index bestA = 0, bestB = 0;
  fit.bestError = fit.errors.minCoeff(&bestA, &bestB);
  fit.best = KernelWidths{grid.sigmaRho[static_cast<std::size_t>(bestA)], grid.sigmaU[static_cast<std::size_t>(bestB)]};
  return fit;
}

}  // namespace deformation_enrichment::enrichment
