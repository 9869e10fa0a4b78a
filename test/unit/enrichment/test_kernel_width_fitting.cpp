// Leave-one-out kernel width fitting on a synthetic set whose stamps vary smoothly with the descriptors.
#include <gtest/gtest.h>

#include <cmath>

#include "deformation_enrichment/enrichment/kernel_width_fitting.hpp"
#include "deformation_enrichment/enrichment/stamp_blending.hpp"
#include "deformation_enrichment/error.hpp"

namespace de = deformation_enrichment;
namespace en = deformation_enrichment::enrichment;
using de::hermite::MomentList;

namespace {

// Examples on a 6 x 6 grid of site parameter t (spacing 0.5) and deformation direction theta (spacing
// 0.25 rad, so neighbouring d_u = 1 - cos 0.25 = 0.031). The stamp depends smoothly on both.
struct SyntheticSet {
  std::vector<MomentList> rho, mu;
  std::vector<cv::Mat> stamps;
};

SyntheticSet syntheticSet(double tFrequency = 1.0) {
  SyntheticSet set;
  for (int a = 0; a < 6; ++a)
    for (int b = 0; b < 6; ++b) {
      const double t = 0.5 * a, theta = 0.25 * b;
      MomentList rho(0, 1, 1);
      rho.values().setZero();
      rho.values()[0] = t;
      MomentList mu(1, 1, 3);
      mu.values().setZero();
      mu.values()[0] = std::cos(theta);
      mu.values()[1] = std::sin(theta);
      cv::Mat stamp(16, 16, CV_32FC3);
      for (int j = 0; j < 16; ++j)
        for (int k = 0; k < 16; ++k)
          stamp.at<cv::Vec3f>(j, k) = cv::Vec3f(float(std::sin(0.4 * k + 0.8 * tFrequency * t) * std::cos(0.3 * j + theta)),
                                                float(std::cos(0.2 * k * tFrequency * t) * 0.5), float(std::sin(2.0 * theta + 0.1 * j)));
      set.rho.push_back(rho);
      set.mu.push_back(mu);
      set.stamps.push_back(stamp);
    }
  return set;
}

}  // namespace

namespace {

// Explicit leave-one-out: per held-out example a fresh table and interpolator of the others, eq. (15)
// weights by correlate(), the eq. (16) stamp by blendStamps() of the stamps scaled by m_k / m_i when
// `magnitudes` are given (magnitude-aware stamps), the prediction scaled by `gain`. With `groups`, the
// examples of k's group are left out with it. Returns the relative error.
double explicitLeaveOneOut(const SyntheticSet& set, const en::KernelWidths& widths, const Eigen::VectorXd& magnitudes,
                           const std::vector<int>& groups = {}, double gain = 1.0) {
  double error = 0.0, norm = 0.0;
  for (std::size_t k = 0; k < set.stamps.size(); ++k) {
    SyntheticSet others;
    for (std::size_t i = 0; i < set.stamps.size(); ++i)
      if (i != k && (groups.empty() || groups[i] != groups[k])) {
        others.rho.push_back(set.rho[i]);
        others.mu.push_back(set.mu[i]);
        cv::Mat stamp = set.stamps[i].clone();
        if (magnitudes.size()) stamp *= magnitudes[Eigen::Index(k)] / magnitudes[Eigen::Index(i)];
        others.stamps.push_back(stamp);
      }
    const en::ExampleDescriptorTable t(others.rho, others.mu);
    const en::RbfInterpolator rbf(en::kernelMatrix(en::exampleDissimilarities(t, others.rho, others.mu), widths));
    en::Correlation c;
    en::correlate(t, set.rho[k], set.mu[k], widths, c);
    en::RbfWeights w;
    rbf.interpolate(c.weights, w);
    const cv::Mat predicted = en::blendStamps(others.stamps, gain * w.weights);
    cv::Mat diff;
    cv::subtract(predicted, set.stamps[k], diff, cv::noArray(), CV_64FC3);
    error += diff.dot(diff);
    cv::Mat exact;
    set.stamps[k].convertTo(exact, CV_64FC3);
    norm += exact.dot(exact);
  }
  return error / norm;
}

}  // namespace

TEST(KernelWidthFitting, GramShortcutMatchesExplicitLeaveOneOut) {
  const SyntheticSet set = syntheticSet();
  const en::ExampleDescriptorTable table(set.rho, set.mu);
  const en::ExampleDissimilarities d = en::exampleDissimilarities(table, set.rho, set.mu);
  const en::KernelWidths widths{0.6, 0.08};
  const Eigen::MatrixXd gram = en::stampGramMatrix(set.stamps);
  const double plain = explicitLeaveOneOut(set, widths, Eigen::VectorXd());
  EXPECT_NEAR(en::leaveOneOutError(d, gram, widths), plain, 1e-6 * plain + 1e-9);
  // Magnitude-aware prediction: the scaled Gram shortcut against scaling the stamps themselves.
  const Eigen::VectorXd magnitudes = Eigen::VectorXd::LinSpaced(Eigen::Index(set.stamps.size()), 0.5, 2.0);
  const double aware = explicitLeaveOneOut(set, widths, magnitudes);
  EXPECT_NEAR(en::leaveOneOutError(d, gram, widths, en::RbfInterpolator::kDefaultRegularisation, magnitudes), aware,
              1e-6 * aware + 1e-9);
  EXPECT_GT(std::abs(aware - plain), 1e-3 * plain);  // the magnitudes do change the prediction
  EXPECT_THROW(en::leaveOneOutError(d, gram, widths, 1e-3, Eigen::VectorXd::Ones(3)), de::InvalidInputError);
}

TEST(KernelWidthFitting, SitesLeaveTogetherAndTheCrossValidatedGainMinimisesTheError) {
  const SyntheticSet set = syntheticSet();
  const en::ExampleDescriptorTable table(set.rho, set.mu);
  const en::ExampleDissimilarities d = en::exampleDissimilarities(table, set.rho, set.mu);
  const Eigen::MatrixXd gram = en::stampGramMatrix(set.stamps);
  const en::KernelWidths widths{0.6, 0.08};
  // Pairs of consecutive examples as sites: each pair is predicted from the other pairs only.
  std::vector<int> pairs, alone;
  for (std::size_t i = 0; i < set.stamps.size(); ++i) pairs.push_back(static_cast<int>(i / 2)), alone.push_back(static_cast<int>(i));
  const double grouped = explicitLeaveOneOut(set, widths, Eigen::VectorXd(), pairs);
  EXPECT_NEAR(en::leaveOneOutError(d, gram, widths, en::RbfInterpolator::kDefaultRegularisation, Eigen::VectorXd(), pairs), grouped,
              1e-6 * grouped + 1e-9);
  EXPECT_NEAR(en::leaveOneOutError(d, gram, widths, en::RbfInterpolator::kDefaultRegularisation, Eigen::VectorXd(), alone),
              en::leaveOneOutError(d, gram, widths), 1e-12);
  EXPECT_GT(std::abs(grouped - explicitLeaveOneOut(set, widths, Eigen::VectorXd())), 1e-3 * grouped);
  // The gain of the fit is the best scale of the held-out predictions (checked against scanning it), in
  // [0, 1], and its error is that of the scaled prediction.
  const en::KernelWidthFit fit = en::fitKernelWidths(d, gram, en::defaultKernelWidthGrid(d, 6),
                                                     en::RbfInterpolator::kDefaultRegularisation, Eigen::VectorXd(), pairs);
  EXPECT_GE(fit.gain, 0.0);
  EXPECT_LE(fit.gain, 1.0);
  EXPECT_NEAR(fit.gainedError, explicitLeaveOneOut(set, fit.best, Eigen::VectorXd(), pairs, fit.gain), 1e-6);
  EXPECT_LE(fit.gainedError, fit.bestError + 1e-12);
  for (const double other : {0.5 * fit.gain, std::min(1.0, 1.2 * fit.gain), 0.0})
    EXPECT_LE(fit.gainedError, explicitLeaveOneOut(set, fit.best, Eigen::VectorXd(), pairs, other) + 1e-9) << other;
}

TEST(KernelWidthFitting, BestWidthsLieWhereTheExampleSpacingSaysAndBeatTheGridEdges) {
  const SyntheticSet set = syntheticSet();
  const en::ExampleDescriptorTable table(set.rho, set.mu);
  const en::ExampleDissimilarities d = en::exampleDissimilarities(table, set.rho, set.mu);
  const Eigen::MatrixXd G = en::stampGramMatrix(set.stamps);
  const en::KernelWidthGrid grid = en::defaultKernelWidthGrid(d, 12);
  ASSERT_EQ(grid.sigmaRho.size(), 12u);
  const en::KernelWidthFit fit = en::fitKernelWidths(d, G, grid);
  // sigma_rho between one and four t spacings (0.5): narrower kernels do not reach the neighbours,
  // wider ones smear the t dependence (the grid runs from 0.05 to 5).
  EXPECT_GE(fit.best.sigmaRho, 0.5);
  EXPECT_LE(fit.best.sigmaRho, 2.0);
  // d_u = 1 - cos(dtheta) is flat at 0, so the kernel in theta is exp(-dtheta^4 / 8 sigma_u^2): reaching
  // the neighbours two steps away (d_u = 0.12) up to the far end of the set (d_u = 0.68) needs
  // sigma_u between those.
  EXPECT_GE(fit.best.sigmaU, 0.12);
  EXPECT_LE(fit.best.sigmaU, 0.68);
  EXPECT_LT(fit.bestError, 0.01);
  // The fit beats both grid corners clearly (too narrow: little overlap; too wide: smeared).
  EXPECT_LT(fit.bestError, 0.1 * fit.errors(0, 0));
  EXPECT_LT(fit.bestError, 0.1 * fit.errors(11, 11));
  EXPECT_EQ(fit.bestError, fit.errors.minCoeff());
  EXPECT_NEAR(fit.bestError, en::leaveOneOutError(d, G, fit.best), 1e-12);
}

TEST(KernelWidthFitting, FasterVaryingStampsGetNarrowerSiteKernels) {
  const auto fitted = [](double frequency) {
    const SyntheticSet set = syntheticSet(frequency);
    const en::ExampleDescriptorTable table(set.rho, set.mu);
    const en::ExampleDissimilarities d = en::exampleDissimilarities(table, set.rho, set.mu);
    return en::fitKernelWidths(d, en::stampGramMatrix(set.stamps), en::defaultKernelWidthGrid(d, 12));
  };
  const en::KernelWidthFit slow = fitted(0.5), fast = fitted(2.0);
  EXPECT_LT(fast.best.sigmaRho, slow.best.sigmaRho);
  EXPECT_LT(slow.bestError, fast.bestError);  // slower variation is easier to interpolate
}

TEST(KernelWidthFitting, BadInputThrows) {
  const SyntheticSet set = syntheticSet();
  const en::ExampleDescriptorTable table(set.rho, set.mu);
  const en::ExampleDissimilarities d = en::exampleDissimilarities(table, set.rho, set.mu);
  const Eigen::MatrixXd G = en::stampGramMatrix(set.stamps);
  EXPECT_THROW(en::leaveOneOutError(d, G.topLeftCorner(3, 3), {}), de::InvalidInputError);
  EXPECT_THROW(en::leaveOneOutError(d, Eigen::MatrixXd::Zero(36, 36), {}), de::InvalidInputError);
  en::ExampleDissimilarities one{Eigen::MatrixXd::Zero(1, 1), Eigen::MatrixXd::Zero(1, 1)};
  EXPECT_THROW(en::leaveOneOutError(one, Eigen::MatrixXd::Ones(1, 1), {}), de::InvalidInputError);
  EXPECT_THROW(en::fitKernelWidths(d, G, en::KernelWidthGrid{{0.1}, {}}), de::InvalidInputError);
  EXPECT_THROW(en::fitKernelWidths(d, G, en::KernelWidthGrid{{-0.1}, {0.1}}), de::InvalidInputError);
  EXPECT_THROW(en::stampGramMatrix({set.stamps[0], cv::Mat(4, 4, CV_32FC3)}), de::InvalidInputError);
}
