#include "deformation_enrichment/enrichment/example_blender.hpp"

#include <algorithm>
#include <string>
#include <vector>

#include "deformation_enrichment/enrichment/stamp_blending.hpp"
#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::enrichment {
namespace {

// Examples at one contact (one site, several patterns) form a group for cross-validation: a new contact is
// predicted from other sites, so a site is left out as a whole. One site only: examples leave one by one.
std::vector<int> siteGroups(const examples::ExampleSet& set) {
  std::vector<int> group(set.examples.size(), -1);
  int sites = 0;
  for (std::size_t i = 0; i < set.examples.size(); ++i) {
    for (std::size_t j = 0; j < i && group[i] < 0; ++j)
      if ((set.examples[i].contact - set.examples[j].contact).norm() <= 1e-9) group[i] = group[j];
    if (group[i] < 0) group[i] = sites++;
  }
  return sites >= 2 ? group : std::vector<int>();
}

double medianNorm(const std::vector<hermite::MomentList>& moments) {
  std::vector<double> norms;
  for (const auto& m : moments) norms.push_back(hermite::norm(m));
  std::nth_element(norms.begin(), norms.begin() + static_cast<long>(norms.size() / 2), norms.end());
  return norms[norms.size() / 2];
}

}  // namespace

BlendMethod parseBlendMethod(const std::string& text) {
  if (text == "paper") return BlendMethod::Paper;
  if (text == "regression") return BlendMethod::Regression;
  throw InvalidInputError("blend '" + text + "' does not exist (paper or regression)");
}

const char* toString(BlendMethod method) { return method == BlendMethod::Paper ? "paper" : "regression"; }

ExampleBlender::ExampleBlender(const examples::ExampleSet& set, const ExampleBlenderOptions& options)
    : lambda_(options.lambda), widths_(options.widths) {
  if (set.examples.empty()) throw InvalidInputError("ExampleBlender: the example set is empty");
  std::vector<hermite::MomentList> rho, mu;
  for (std::size_t i = 0; i < set.examples.size(); ++i) {
    const examples::Example& e = set.examples[i];
    examples::validateExample(e, "ExampleBlender: example " + std::to_string(i));
    rho.push_back(e.rho);
    mu.push_back(e.mu);
    stamps_.push_back(e.stamp);
  }
  // Throws for differing stamp grids; the blended stamp of all-zero weights also fixes the radius.
  blendExampleStamps(set.examples, Eigen::VectorXd::Zero(size()), radius_);
  layers_ = set.examples.front().stampLayers;
  table_ = std::make_unique<ExampleDescriptorTable>(rho, mu);
  dissimilarities_ = exampleDissimilarities(*table_, rho, mu);
  for (const auto& m : mu) largestMuNorm_ = std::max(largestMuNorm_, m.values().norm());
  const Eigen::MatrixXd gram = size() >= 2 ? stampGramMatrix(stamps_) : Eigen::MatrixXd();
  // Regression needs two examples to leave one out, and something to regress (else the paper's blend, which
  // adds nothing for zero stamps either).
  if (options.method == BlendMethod::Regression && size() >= 2 && gram.trace() > 0.0 && largestMuNorm_ > 0.0) {
    regression_ = std::make_unique<StampRegression>(rho, mu, gram);
    if (options.crossValidatedGain) gain_ = regression_->fit().gain;
  } else if (options.fitWidths && size() >= 2) {
    if (gram.trace() > 0.0) {  // all-zero stamps: nothing to cross-validate, keep the given widths
      Eigen::VectorXd magnitudes;
      if (options.magnitudeAware) {
        magnitudes.resize(size());
        for (Eigen::Index i = 0; i < size(); ++i) magnitudes[i] = mu[static_cast<std::size_t>(i)].values().norm();
      }
      fit_ = fitKernelWidths(dissimilarities_, gram,
                             defaultKernelWidthGrid(dissimilarities_, options.gridCount, options.siteResolution * medianNorm(rho)),
                             lambda_, magnitudes, siteGroups(set));
      widths_ = fit_->best;
      if (options.crossValidatedGain) gain_ = fit_->gain;
    }
  }
  setWidths(widths_);
}

void ExampleBlender::setWidths(const KernelWidths& widths) {
  rbf_ = std::make_unique<RbfInterpolator>(kernelMatrix(dissimilarities_, widths), lambda_);
  widths_ = widths;
}

void ExampleBlender::blend(const hermite::MomentList& rho, const hermite::MomentList& mu, BlendResult& out) const {
  if (regression_) {
    regression_->weights(rho, mu, out.rbf.weights, out.rbf.confidence);
  } else {
    correlate(*table_, rho, mu, widths_, out.correlation);  // eq. (15)
    rbf_->interpolate(out.correlation.weights, out.rbf);
  }
  if (gain_ != 1.0) out.rbf.weights *= gain_;
  out.stamp = blendStamps(stamps_, out.rbf.weights);  // eq. (16)
}

}  // namespace deformation_enrichment::enrichment
