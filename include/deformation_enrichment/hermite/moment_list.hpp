#pragma once
// A list of Hermite moments tau = (tau_first, ..., tau_last) ([Seiler14 §4.1]), each a symmetric tensor
// stored by distinct components, for `channels` scalar functions (1 for the density rho, 3 for the
// displacement components of mu). Values are contiguous: channel-major, then order, then component.
#include <Eigen/Core>

namespace deformation_enrichment::hermite {

class MomentList {
public:
  MomentList() = default;
  /// Zero moments of orders firstOrder..lastOrder (within [0, kMaxHermiteOrder]); channels is 1 or 3.
  MomentList(int firstOrder, int lastOrder, int channels = 1);

  int firstOrder() const { return firstOrder_; }
  int lastOrder() const { return lastOrder_; }
  int channels() const { return channels_; }
  /// Number of values per channel.
  int channelSize() const { return channelSize_; }
  bool empty() const { return values_.size() == 0; }

  Eigen::VectorXd& values() { return values_; }
  const Eigen::VectorXd& values() const { return values_; }

  /// Distinct components of order n of one channel.
  Eigen::VectorXd::SegmentReturnType order(int n, int channel = 0);
  Eigen::VectorXd::ConstSegmentReturnType order(int n, int channel = 0) const;

  /// Multiplicity of every value (the metric of the full-tensor dot product), same layout as values().
  Eigen::VectorXd multiplicities() const;

  /// Basis transformation of every tensor (Appendix B). For three channels the channel index is a vector
  /// index too (mu_n is u (x) H_n) and is transformed by T as well.
  MomentList transformed(const Eigen::Matrix3d& T) const;

private:
  int firstOrder_ = 0;
  int lastOrder_ = -1;
  int channels_ = 0;
  int channelSize_ = 0;
  Eigen::VectorXd values_;
};

/// <tau, v> = sum_n tau_n . v_n over orders and channels (eq. 6 and 13). Throws InvalidInputError when the
/// layouts differ.
double inner(const MomentList& a, const MomentList& b);

/// sqrt(<tau, tau>) (the Hermitian norm; the paper's shorthand drops the square root).
double norm(const MomentList& a);

}  // namespace deformation_enrichment::hermite
