#pragma once
// The run-time chain for one contact, built once per loaded example set: weights of the current (rho, mu)
// for every example, then the blended stamp Psi = sum_i w~_i Psi[i] (eq. 16). Two ways to the weights:
//   - BlendMethod::Paper, [Seiler14 §5]: eq. (15) weights -> RBF interpolation with the examples'
//     regularised kernel matrix, the kernel widths fitted by leave-one-out cross-validation when the set is
//     loaded (examples at one contact, several patterns of one site, leave together: leave-one-site-out);
//   - BlendMethod::Regression (the package's default, KnobOptions::blend): the stamp regression of stamp_regression.hpp, which generalises
//     to contacts the set does not hold (docs/accuracy.md). A set of one example blends as the paper does.
#include <Eigen/Core>
#include <memory>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "deformation_enrichment/enrichment/blending_weights.hpp"
#include "deformation_enrichment/enrichment/kernel_width_fitting.hpp"
#include "deformation_enrichment/enrichment/rbf_interpolation.hpp"
#include "deformation_enrichment/enrichment/stamp_regression.hpp"
#include "deformation_enrichment/examples/example.hpp"

namespace deformation_enrichment::enrichment {

enum class BlendMethod { Paper, Regression };
/// "paper" or "regression"; throws InvalidInputError naming the text otherwise.
BlendMethod parseBlendMethod(const std::string& text);
const char* toString(BlendMethod method);

struct ExampleBlenderOptions {
  BlendMethod method = BlendMethod::Paper;  ///< the node, de_evaluate and acquisition default to Regression
  bool fitWidths = true;           ///< paper: leave-one-out fit at construction (needs >= 2 examples)
  KernelWidths widths;             ///< used when not fitting
  int gridCount = 12;              ///< defaultKernelWidthGrid size per width
  double lambda = RbfInterpolator::kDefaultRegularisation;
  /// Fit the widths for magnitude-aware stamps (contact_enricher.hpp), i.e. predicting with |mu| / |mu[i]|.
  bool magnitudeAware = false;
  /// Scale w~ by the fit's cross-validated gain (KernelWidthFit::gain, StampRegressionFit::gain): a set whose
  /// examples do not predict each other fades its detail. Without a fit the gain is 1.
  bool crossValidatedGain = true;
  /// Resolution of the site descriptor, relative to the median |rho[i]|: the fitted sigma_rho is at least
  /// this (defaultKernelWidthGrid's floor). Sites whose rho differ by less are the same site up to
  /// sampling noise (on a slab whose examples all sit on equivalent sites the unbounded fit chose
  /// 3e-4 |rho| and a sliding contact's detail changed by 50 % per 0.25 mm; docs/design.md §4).
  /// 0 = the paper's unbounded fit.
  double siteResolution = 1e-2;
};

struct BlendResult {
  Correlation correlation;  ///< d_rho, d_u, eq. (15) weights (paper)
  RbfWeights rbf;           ///< w~ and the confidence (paper: max eq. 15 weight; regression: explained variance)
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
  int stampLayers() const { return layers_; }
  const std::vector<cv::Mat>& stamps() const { return stamps_; }
  const KernelWidths& widths() const { return widths_; }
  /// The method in use (a one-example set blends as the paper does).
  BlendMethod method() const { return regression_ ? BlendMethod::Regression : BlendMethod::Paper; }
  /// The paper's leave-one-out fit, if one was run.
  const std::optional<KernelWidthFit>& fit() const { return fit_; }
  /// The stamp regression, when that is the method.
  const StampRegression* regression() const { return regression_.get(); }
  /// The largest |mu[i]| of the examples.
  double largestMuNorm() const { return largestMuNorm_; }
  /// The factor on w~ (the fit's cross-validated gain, or 1).
  double gain() const { return gain_; }

  /// New eq. (15) widths (e.g. reconfigured at run time): rebuilds the RBF interpolator (O(N^3)). The
  /// regression keeps its own fit.
  void setWidths(const KernelWidths& widths);

  /// Weights -> eq. (16) for descriptors expressed in the current stamping frame. `out` is reused.
  void blend(const hermite::MomentList& rho, const hermite::MomentList& mu, BlendResult& out) const;

private:
  std::unique_ptr<ExampleDescriptorTable> table_;
  ExampleDissimilarities dissimilarities_;
  std::unique_ptr<RbfInterpolator> rbf_;
  std::vector<cv::Mat> stamps_;
  double radius_ = 0.0;
  int layers_ = 1;
  double lambda_;
  KernelWidths widths_;
  std::optional<KernelWidthFit> fit_;
  std::unique_ptr<StampRegression> regression_;
  double gain_ = 1.0;
  double largestMuNorm_ = 0.0;
};

}  // namespace deformation_enrichment::enrichment
