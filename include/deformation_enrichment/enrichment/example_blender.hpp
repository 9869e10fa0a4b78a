#pragma once
// The run-time chain of [Seiler14 §5] for one contact, built once per loaded example set:
//   eq. (15) weights of the current (rho, mu) against every example -> RBF interpolation with the
//   examples' regularised kernel matrix -> blended stamp Psi = sum_i w~_i Psi[i] (eq. 16),
// with the kernel widths fitted by leave-one-out cross-validation when the set is loaded (examples at one
// contact, several patterns of one site, leave together: leave-one-site-out).
#include <Eigen/Core>
#include <memory>
#include <opencv2/core.hpp>
#include <optional>
#include <vector>

#include "deformation_enrichment/enrichment/blending_weights.hpp"
#include "deformation_enrichment/enrichment/kernel_width_fitting.hpp"
#include "deformation_enrichment/enrichment/rbf_interpolation.hpp"
#include "deformation_enrichment/examples/example.hpp"

namespace deformation_enrichment::enrichment {

struct ExampleBlenderOptions {
  bool fitWidths = true;           ///< leave-one-out fit at construction (needs >= 2 examples)
  KernelWidths widths;             ///< used when not fitting
  int gridCount = 12;              ///< defaultKernelWidthGrid size per width
  double lambda = RbfInterpolator::kDefaultRegularisation;
  /// Fit the widths for magnitude-aware stamps (contact_enricher.hpp), i.e. predicting with |mu| / |mu[i]|.
  bool magnitudeAware = false;
  /// Scale w~ by the fit's cross-validated gain (KernelWidthFit::gain): a set whose examples do not predict
  /// each other fades its detail. Without a fit the gain is 1.
  bool crossValidatedGain = true;
  /// Resolution of the site descriptor, relative to the median |rho[i]|: the fitted sigma_rho is at least
  /// this (defaultKernelWidthGrid's floor). Sites whose rho differ by less are the same site up to
  /// sampling noise (on a slab whose examples all sit on equivalent sites the unbounded fit chose
  /// 3e-4 |rho| and a sliding contact's detail changed by 50 % per 0.25 mm; docs/design.md §4).
  /// 0 = the paper's unbounded fit.
  double siteResolution = 1e-2;
};

struct BlendResult {
  Correlation correlation;  ///< d_rho, d_u, eq. (15) weights
  RbfWeights rbf;           ///< w~ and the confidence
  cv::Mat stamp;            ///< eq. (16), CV_32FC3 over [-radius, radius]^2
};

class ExampleBlender {
public:
  /// Throws InvalidInputError for an empty set, invalid examples, descriptor layouts or stamp grids that
  /// differ between examples; NumericalError if no kernel matrix can be factorised. With one example
  /// the widths are not fitted (leave-one-out needs two) and options.widths are used.
  explicit ExampleBlender(const examples::ExampleSet& set, const ExampleBlenderOptions& options = {});

  Eigen::Index size() const { return static_cast<Eigen::Index>(stamps_.size()); }
  double stampRadius() const { return radius_; }
  const std::vector<cv::Mat>& stamps() const { return stamps_; }
  const KernelWidths& widths() const { return widths_; }
  /// The leave-one-out fit, if one was run.
  const std::optional<KernelWidthFit>& fit() const { return fit_; }
  /// The factor on w~ (the fit's cross-validated gain, or 1).
  double gain() const { return gain_; }

  /// New widths (e.g. reconfigured at run time): rebuilds the RBF interpolator (O(N^3)).
  void setWidths(const KernelWidths& widths);

  /// eq. (15) -> RBF -> eq. (16) for descriptors expressed in the current stamping frame. `out` is reused.
  void blend(const hermite::MomentList& rho, const hermite::MomentList& mu, BlendResult& out) const;

private:
  std::unique_ptr<ExampleDescriptorTable> table_;
  ExampleDissimilarities dissimilarities_;
  std::unique_ptr<RbfInterpolator> rbf_;
  std::vector<cv::Mat> stamps_;
  double radius_ = 0.0;
  double lambda_;
  KernelWidths widths_;
  std::optional<KernelWidthFit> fit_;
  double gain_ = 1.0;
};

}  // namespace deformation_enrichment::enrichment
