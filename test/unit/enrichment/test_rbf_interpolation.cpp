// RBF interpolation of the eq. (15) weights: interpolation property, coinciding examples, confidence.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "deformation_enrichment/enrichment/rbf_interpolation.hpp"
#include "deformation_enrichment/error.hpp"

namespace de = deformation_enrichment;
namespace en = deformation_enrichment::enrichment;
using de::hermite::MomentList;

namespace {

struct Descriptors {
  std::vector<MomentList> rho, mu;
};

// Site descriptor (t, s) in the order-0/1 slots, deformation direction at angle theta.
void add(Descriptors& d, double t, double s, double theta) {
  MomentList rho(0, 1, 1);
  rho.values().setZero();
  rho.values()[0] = t;
  rho.values()[1] = s;
  MomentList mu(1, 1, 3);
  mu.values().setZero();
  mu.values()[0] = std::cos(theta);
  mu.values()[1] = std::sin(theta);
  d.rho.push_back(rho);
  d.mu.push_back(mu);
}

Descriptors spreadExamples(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Descriptors d;
  for (int i = 0; i < n; ++i) add(d, 3.0 * u(rng), 3.0 * u(rng), 1.5 * u(rng));
  return d;
}

}  // namespace

TEST(RbfInterpolation, KernelMatrixIsEq15BetweenExamples) {
  const Descriptors d = spreadExamples(8, 1);
  const en::ExampleDescriptorTable table(d.rho, d.mu);
  const en::KernelWidths widths{0.7, 0.3};
  const Eigen::MatrixXd K = en::kernelMatrix(en::exampleDissimilarities(table, d.rho, d.mu), widths);
  for (int i = 0; i < 8; ++i)
    for (int j = 0; j < 8; ++j) {
      // Independent evaluation from the raw values (order 0 and 1 components have multiplicity 1).
      const double dRho = (d.rho[i].values() - d.rho[j].values()).norm();
      const double cosine = d.mu[i].values().dot(d.mu[j].values()) / (d.mu[i].values().norm() * d.mu[j].values().norm());
      const double dU = 1.0 - cosine;
      const double expected = std::exp(-dRho * dRho / (2 * 0.49) - dU * dU / (2 * 0.09));
      EXPECT_NEAR(K(i, j), expected, 1e-12) << i << "," << j;
    }
}

TEST(RbfInterpolation, QueryAtAnExampleGivesItsUnitVector) {
  const Descriptors d = spreadExamples(12, 2);
  const en::ExampleDescriptorTable table(d.rho, d.mu);
  const en::KernelWidths widths{0.8, 0.4};
  const en::RbfInterpolator rbf(en::kernelMatrix(en::exampleDissimilarities(table, d.rho, d.mu), widths));
  en::Correlation c;
  en::RbfWeights out;
  for (int i = 0; i < 12; ++i) {
    en::correlate(table, d.rho[i], d.mu[i], widths, c);
    rbf.interpolate(c.weights, out);
    Eigen::VectorXd expected = Eigen::VectorXd::Zero(12);
    expected[i] = 1.0;
    EXPECT_LT((out.weights - expected).cwiseAbs().maxCoeff(), 1e-3) << "example " << i;  // lambda^2 / sigma_min(K)^2
    EXPECT_NEAR(out.confidence, 1.0, 1e-12);
  }
}

TEST(RbfInterpolation, RegularisationErrorShrinksWithLambda) {
  const Descriptors d = spreadExamples(10, 3);
  const en::ExampleDescriptorTable table(d.rho, d.mu);
  const en::KernelWidths widths{0.6, 0.3};
  const Eigen::MatrixXd K = en::kernelMatrix(en::exampleDissimilarities(table, d.rho, d.mu), widths);
  double previous = 1.0;
  for (double lambda : {1e-1, 1e-2, 1e-3}) {
    const en::RbfInterpolator rbf(K, lambda);
    const double error = (rbf.interpolationMatrix() * K - Eigen::MatrixXd::Identity(10, 10)).cwiseAbs().maxCoeff();
    EXPECT_LT(error, previous);
    previous = error;
  }
  EXPECT_LT(previous, 1e-3);
}

TEST(RbfInterpolation, CoincidingExamplesStaySolvableAndShareTheWeight) {
  Descriptors d = spreadExamples(6, 4);
  d.rho.push_back(d.rho[2]);  // example 6 coincides with example 2
  d.mu.push_back(d.mu[2]);
  const en::ExampleDescriptorTable table(d.rho, d.mu);
  const en::KernelWidths widths{0.8, 0.4};
  const en::RbfInterpolator rbf(en::kernelMatrix(en::exampleDissimilarities(table, d.rho, d.mu), widths));
  EXPECT_TRUE(rbf.interpolationMatrix().allFinite());
  en::Correlation c;
  en::RbfWeights out;
  en::correlate(table, d.rho[2], d.mu[2], widths, c);
  rbf.interpolate(c.weights, out);
  EXPECT_NEAR(out.weights[2], 0.5, 1e-3);
  EXPECT_NEAR(out.weights[6], 0.5, 1e-3);
  EXPECT_NEAR(out.weights.sum(), 1.0, 2e-3);
  EXPECT_LT(out.weights.cwiseAbs().maxCoeff(), 0.51);
}

TEST(RbfInterpolation, ConfidenceAndDetailFadeAwayFromTheExamples) {
  const Descriptors d = spreadExamples(10, 5);
  const en::ExampleDescriptorTable table(d.rho, d.mu);
  const en::KernelWidths widths{0.8, 0.4};
  const en::RbfInterpolator rbf(en::kernelMatrix(en::exampleDissimilarities(table, d.rho, d.mu), widths));
  en::Correlation c;
  en::RbfWeights out;
  double previousConfidence = 2.0;
  double lastNorm = 0.0;
  for (double offset : {0.0, 1.0, 2.0, 4.0, 8.0, 16.0}) {
    Descriptors q;
    add(q, d.rho[0].values()[0] - offset, d.rho[0].values()[1] - offset, 0.2);
    en::correlate(table, q.rho[0], q.mu[0], widths, c);
    rbf.interpolate(c.weights, out);
    EXPECT_GE(out.confidence, 0.0);
    EXPECT_LE(out.confidence, 1.0);
    if (offset >= 4.0) {
      EXPECT_LT(out.confidence, previousConfidence);
    }
    previousConfidence = out.confidence;
    lastNorm = out.weights.cwiseAbs().sum();
  }
  EXPECT_LT(previousConfidence, 1e-50);
  EXPECT_LT(lastNorm, 1e-40);  // w~ is linear in w: no example similar, no detail
}

TEST(RbfInterpolation, BadInputThrows) {
  EXPECT_THROW(en::RbfInterpolator(Eigen::MatrixXd(0, 0)), de::InvalidInputError);
  EXPECT_THROW(en::RbfInterpolator(Eigen::MatrixXd::Identity(2, 3)), de::InvalidInputError);
  Eigen::MatrixXd K = Eigen::MatrixXd::Identity(3, 3);
  EXPECT_THROW(en::RbfInterpolator(K, 0.0), de::InvalidInputError);
  K(0, 1) = std::nan("");
  EXPECT_THROW(en::RbfInterpolator{K}, de::InvalidInputError);
  K(0, 1) = 2.0;
  EXPECT_THROW(en::RbfInterpolator{K}, de::InvalidInputError);
  const en::RbfInterpolator rbf(Eigen::MatrixXd::Identity(3, 3));
  en::RbfWeights out;
  EXPECT_THROW(rbf.interpolate(Eigen::VectorXd::Ones(2), out), de::InvalidInputError);
  EXPECT_THROW(rbf.interpolate(Eigen::Vector3d(0.1, std::nan(""), 0.2), out), de::InvalidInputError);
  EXPECT_THROW(rbf.interpolate(Eigen::Vector3d(0.1, -0.5, 0.2), out), de::InvalidInputError);
  const Descriptors d = spreadExamples(3, 6);
  const en::ExampleDescriptorTable table(d.rho, d.mu);
  EXPECT_THROW(en::exampleDissimilarities(table, {d.rho[0]}, d.mu), de::InvalidInputError);
}
