#include "deformation_enrichment/enrichment/blending_weights.hpp"

#include <cmath>
#include <string>

#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::enrichment {

namespace {
bool sameLayout(const hermite::MomentList& a, const hermite::MomentList& b) {
  return a.firstOrder() == b.firstOrder() && a.lastOrder() == b.lastOrder() && a.channels() == b.channels();
}

void checkWidths(const KernelWidths& widths) {
  if (!(widths.sigmaRho > 0.0) || !std::isfinite(widths.sigmaRho) || !(widths.sigmaU > 0.0) ||
      !std::isfinite(widths.sigmaU))
    throw InvalidInputError("blending weights: kernel widths must be positive and finite");
}

// Scaled by the largest entry before squaring, so no underflow for tiny descriptors.
double scaledNorm(const Eigen::VectorXd& v) {
  const double scale = v.cwiseAbs().maxCoeff();
  return scale > 0.0 ? scale * (v / scale).norm() : 0.0;
}
}  // namespace

ExampleDescriptorTable::ExampleDescriptorTable(const std::vector<hermite::MomentList>& rho,
                                               const std::vector<hermite::MomentList>& mu) {
  if (rho.empty()) throw InvalidInputError("example table: no examples");
  if (mu.size() != rho.size())
    throw InvalidInputError("example table: " + std::to_string(rho.size()) + " site and " +
                            std::to_string(mu.size()) + " deformation descriptors");
  rhoLayout_ = rho.front();
  muLayout_ = mu.front();
  rhoMetric_ = rhoLayout_.multiplicities().cwiseSqrt();
  muMetric_ = muLayout_.multiplicities().cwiseSqrt();
  const Eigen::VectorXd& rhoMetric = rhoMetric_;
  const Eigen::VectorXd& muMetric = muMetric_;
  const Eigen::Index count = static_cast<Eigen::Index>(rho.size());
  rho_.resize(rhoMetric.size(), count);
  muUnit_.resize(muMetric.size(), count);
  muZero_.resize(count);
  for (Eigen::Index i = 0; i < count; ++i) {
    if (!sameLayout(rho[i], rhoLayout_) || !sameLayout(mu[i], muLayout_))
      throw InvalidInputError("example table: example " + std::to_string(i) + " has a different layout");
    if (!rho[i].values().allFinite() || !mu[i].values().allFinite())
      throw InvalidInputError("example table: example " + std::to_string(i) + " contains NaN or Inf");
    rho_.col(i) = rhoMetric.cwiseProduct(rho[i].values());
    const Eigen::VectorXd scaled = muMetric.cwiseProduct(mu[i].values());
    const double length = scaledNorm(scaled);
    muZero_[i] = length == 0.0;
    muUnit_.col(i) = muZero_[i] ? Eigen::VectorXd::Zero(scaled.size()) : Eigen::VectorXd(scaled / length);
  }
  rhoSquaredNorm_ = rho_.colwise().squaredNorm().transpose();
}

void correlate(const ExampleDescriptorTable& examples, const hermite::MomentList& rho,
               const hermite::MomentList& mu, const KernelWidths& widths, Correlation& out) {
  checkWidths(widths);
  if (!sameLayout(rho, examples.rhoLayout()) || !sameLayout(mu, examples.muLayout()))
    throw InvalidInputError("correlate: descriptor layout differs from the examples'");
  if (!rho.values().allFinite() || !mu.values().allFinite())
    throw InvalidInputError("correlate: current descriptor contains NaN or Inf");
  const Eigen::VectorXd rhoQuery = examples.rhoMetric().cwiseProduct(rho.values());
  Eigen::VectorXd muQuery = examples.muMetric().cwiseProduct(mu.values());
  const double muLength = scaledNorm(muQuery);
  const Eigen::Index count = examples.size();
  out.dRho.resize(count);
  out.dU.resize(count);
  out.weights.resize(count);

  // eq. (9) in the metric-scaled space, expanded as |q|^2 + |e_i|^2 - 2 <q, e_i>: one matrix-vector product
  // over the contiguous table. Where that cancels badly (d_rho^2 below 1e-6 of the norms) the difference
  // is summed directly, so near-identical descriptors keep full precision.
  const double querySquaredNorm = rhoQuery.squaredNorm();
  out.dRho.noalias() = examples.rho().transpose() * rhoQuery;
  out.dRho = (examples.rhoSquaredNorm().array() + querySquaredNorm - 2.0 * out.dRho.array()).max(0.0).matrix();
  for (Eigen::Index i = 0; i < count; ++i) {
    if (out.dRho[i] < 1e-6 * (examples.rhoSquaredNorm()[i] + querySquaredNorm))
      out.dRho[i] = (examples.rho().col(i) - rhoQuery).squaredNorm();
  }
  out.dRho = out.dRho.cwiseSqrt();
  // eq. (14): 1 - cosine; the cosines of all examples are one matrix-vector product.
  if (muLength > 0.0) {
    muQuery /= muLength;
    out.dU.noalias() = examples.muUnit().transpose() * muQuery;
    out.dU = (1.0 - out.dU.array()).max(0.0).min(2.0).matrix();
    out.dU = examples.muZero().select(Eigen::VectorXd::Ones(count), out.dU);
  } else {
    out.dU = examples.muZero().select(Eigen::VectorXd::Zero(count), Eigen::VectorXd::Ones(count));
  }
  // eq. (15)
  const double a = 0.5 / (widths.sigmaRho * widths.sigmaRho), b = 0.5 / (widths.sigmaU * widths.sigmaU);
  out.weights = (-(a * out.dRho.array().square() + b * out.dU.array().square())).exp().matrix();
}

Eigen::VectorXd blendingWeights(const Eigen::VectorXd& dRho, const Eigen::VectorXd& dU, const KernelWidths& widths) {
  checkWidths(widths);
  if (dRho.size() != dU.size()) throw InvalidInputError("blending weights: d_rho and d_u sizes differ");
  if (!dRho.allFinite() || !dU.allFinite()) throw InvalidInputError("blending weights: NaN dissimilarity");
  // eq. (15)
  return (-(dRho.array().square() / (2.0 * widths.sigmaRho * widths.sigmaRho) +
            dU.array().square() / (2.0 * widths.sigmaU * widths.sigmaU)))
      .exp()
      .matrix();
}

}  // namespace deformation_enrichment::enrichment
