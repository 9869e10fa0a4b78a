#include "deformation_enrichment/hermite/moment_list.hpp"

#include <cmath>
#include <string>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/hermite/hermite_basis.hpp"
#include "deformation_enrichment/hermite/multi_index.hpp"
#include "deformation_enrichment/hermite/symmetric_tensor.hpp"

namespace deformation_enrichment::hermite {

MomentList::MomentList(int firstOrder, int lastOrder, int channels)
    : firstOrder_(firstOrder), lastOrder_(lastOrder), channels_(channels) {
  if (channels != 1 && channels != 3)
    throw InvalidInputError("MomentList: channels must be 1 or 3, got " + std::to_string(channels));
  channelSize_ = basisSize(firstOrder, lastOrder);
  values_ = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(channelSize_) * channels_);
}

namespace {
Eigen::Index startOf(int firstOrder, int lastOrder, int channelSize, int channels, int n, int channel) {
  if (n < firstOrder || n > lastOrder || channel < 0 || channel >= channels)
    throw InvalidInputError("MomentList: order " + std::to_string(n) + " / channel " +
                            std::to_string(channel) + " not stored");
  return static_cast<Eigen::Index>(channel) * channelSize + orderOffset(n) - orderOffset(firstOrder);
}
}  // namespace

Eigen::VectorXd::SegmentReturnType MomentList::order(int n, int channel) {
  return values_.segment(startOf(firstOrder_, lastOrder_, channelSize_, channels_, n, channel),
                         numComponents(n));
}

Eigen::VectorXd::ConstSegmentReturnType MomentList::order(int n, int channel) const {
  return values_.segment(startOf(firstOrder_, lastOrder_, channelSize_, channels_, n, channel),
                         numComponents(n));
}

Eigen::VectorXd MomentList::multiplicities() const {
  Eigen::VectorXd weights(values_.size());
  Eigen::Index position = 0;
  for (int c = 0; c < channels_; ++c)
    for (int n = firstOrder_; n <= lastOrder_; ++n)
      for (const MultiIndex& alpha : multiIndices(n)) weights[position++] = multiplicity(alpha);
  return weights;
}

MomentList MomentList::transformed(const Eigen::Matrix3d& T) const {
  MomentList result(*this);
  for (int n = firstOrder_; n <= lastOrder_; ++n) {
    const Eigen::MatrixXd map = symmetricTransform(n, T);
    for (int c = 0; c < channels_; ++c) result.order(n, c) = map * order(n, c);
    if (channels_ == 3) {
      // The displacement component index transforms like a vector: u'_i = T_ij u_j.
      Eigen::MatrixXd perChannel(map.rows(), 3);
      for (int c = 0; c < 3; ++c) perChannel.col(c) = result.order(n, c);
      const Eigen::MatrixXd mixed = perChannel * T.transpose();
      for (int c = 0; c < 3; ++c) result.order(n, c) = mixed.col(c);
    }
  }
  return result;
}

double inner(const MomentList& a, const MomentList& b) {
  if (a.firstOrder() != b.firstOrder() || a.lastOrder() != b.lastOrder() || a.channels() != b.channels())
    throw InvalidInputError("inner: moment lists have different orders or channels");
  // eq. (6)/(13): full-tensor dot products summed over orders and channels.
  return (a.multiplicities().array() * a.values().array() * b.values().array()).sum();
}

double norm(const MomentList& a) {
  // Scaled by the largest entry so that tiny or huge moments neither underflow nor overflow.
  const double scale = a.values().cwiseAbs().maxCoeff();
  if (!(scale > 0.0) || !std::isfinite(scale)) return scale > 0.0 ? scale : 0.0;
  const Eigen::ArrayXd scaled = a.values().array() / scale;
  return scale * std::sqrt((a.multiplicities().array() * scaled * scaled).sum());
}

}  // namespace deformation_enrichment::hermite
