#include "deformation_enrichment/enrichment/blending_weights.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::enrichment {

namespace {
// Examples per pass of correlate(): a block's outputs (3 x 32 KB) stay in the second-level cache. Even, so
// that blocks split no SIMD packet of an output vector.
constexpr Eigen::Index kCorrelationBlock = 4096;
// From this many examples (a 13 MB table) the blocks are shared among threads.
constexpr Eigen::Index kParallelCorrelation = 32768;

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

// The current descriptors in the table's metric, and the eq. (15) exponents' factors.
struct ScaledQuery {
  Eigen::VectorXd rho, mu;  // mu unit length, unless muLength is 0
  double muLength = 0.0, rhoSquaredNorm = 0.0, a = 0.0, b = 0.0;
};

// d_rho, d_u and the weights of examples [first, first + n) into `out` (sized for every example).
void correlateExamples(const ExampleDescriptorTable& examples, const ScaledQuery& query, Eigen::Index first,
                       Eigen::Index n, Correlation& out) {
  auto dRho = out.dRho.segment(first, n);
  auto dU = out.dU.segment(first, n);
  const auto squaredNorms = examples.rhoSquaredNorm().segment(first, n);
  const auto muZero = examples.muZero().segment(first, n);
  // eq. (9) in the metric-scaled space, expanded as |q|^2 + |e_i|^2 - 2 <q, e_i>: a matrix-vector product
  // over the contiguous table. Where that cancels badly (d_rho^2 below 1e-6 of the norms) the difference
  // is summed directly, so near-identical descriptors keep full precision.
  dRho.noalias() = examples.rho().middleCols(first, n).transpose() * query.rho;
  dRho = (squaredNorms.array() + query.rhoSquaredNorm - 2.0 * dRho.array()).max(0.0).matrix();
  for (Eigen::Index i = 0; i < n; ++i) {
    if (dRho[i] < 1e-6 * (squaredNorms[i] + query.rhoSquaredNorm))
      dRho[i] = (examples.rho().col(first + i) - query.rho).squaredNorm();
  }
  dRho = dRho.cwiseSqrt();
  // eq. (14): 1 - cosine; the cosines are one matrix-vector product.
  if (query.muLength > 0.0) {
    dU.noalias() = examples.muUnit().middleCols(first, n).transpose() * query.mu;
    dU = (1.0 - dU.array()).max(0.0).min(2.0).matrix();
    dU = muZero.select(Eigen::VectorXd::Ones(n), dU);
  } else {
    dU = muZero.select(Eigen::VectorXd::Zero(n), Eigen::VectorXd::Ones(n));
  }
  // eq. (15)
  out.weights.segment(first, n) = (-(query.a * dRho.array().square() + query.b * dU.array().square())).exp().matrix();
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
  ScaledQuery query;
  query.rho = examples.rhoMetric().cwiseProduct(rho.values());
  query.mu = examples.muMetric().cwiseProduct(mu.values());
  query.muLength = scaledNorm(query.mu);
  if (query.muLength > 0.0) query.mu /= query.muLength;
  query.rhoSquaredNorm = query.rho.squaredNorm();
  query.a = 0.5 / (widths.sigmaRho * widths.sigmaRho);
  query.b = 0.5 / (widths.sigmaU * widths.sigmaU);
  const Eigen::Index count = examples.size();
  out.dRho.resize(count);
  out.dU.resize(count);
  out.weights.resize(count);
  // One pass per block of examples, its outputs still in cache from one equation to the next. A table larger
  // than the last-level cache is bound by memory bandwidth, which a second thread nearly doubles. Every
  // example's numbers are those of one pass over the whole table, on any thread count: blocks hold whole
  // SIMD packets, and the last one takes the rest, never a lone example (Eigen's product with one row is a
  // dot product, summed in another order).
  const Eigen::Index blocks = std::max<Eigen::Index>(1, (count + kCorrelationBlock - 2) / kCorrelationBlock);
  const auto correlateBlock = [&](Eigen::Index block) {
    const Eigen::Index first = block * kCorrelationBlock;
    correlateExamples(examples, query, first, block + 1 < blocks ? kCorrelationBlock : count - first, out);
  };
  // A parallel region costs a microsecond even on one thread: small tables never enter one.
  if (count < kParallelCorrelation) {
    for (Eigen::Index block = 0; block < blocks; ++block) correlateBlock(block);
    return;
  }
#pragma omp parallel for schedule(static)
  for (Eigen::Index block = 0; block < blocks; ++block) correlateBlock(block);
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
