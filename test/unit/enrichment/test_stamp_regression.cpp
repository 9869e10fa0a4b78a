// Stamp regression: a stamp field linear in mu at one site is recovered for a new mu, the closed-form
// leave-one-out error equals refitting without each example, detail fades far from every site, bad input throws.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <cmath>
#include <random>

#include "deformation_enrichment/enrichment/example_blender.hpp"
#include "deformation_enrichment/enrichment/kernel_width_fitting.hpp"
#include "deformation_enrichment/enrichment/stamp_regression.hpp"
#include "deformation_enrichment/error.hpp"

namespace de = deformation_enrichment;
namespace en = deformation_enrichment::enrichment;
using de::hermite::MomentList;

namespace {

MomentList site(double t) {
  MomentList rho(0, 1, 1);
  rho.values() << 1.0, t, 0.0, -0.5 * t;
  return rho;
}

MomentList deformation(const Eigen::Vector3d& a) {
  MomentList mu(1, 1, 3);
  mu.values().setZero();
  mu.values().head<3>() = a;
  mu.values()[4] = 0.5 * a.x() - a.z();
  return mu;
}

// Stamp field of a site: linear in mu (three fixed 4 x 4 patterns weighted by mu's first three values).
cv::Mat linearStamp(const MomentList& mu, double t) {
  cv::Mat stamp(4, 4, CV_32FC3);
  for (int j = 0; j < 4; ++j)
    for (int k = 0; k < 4; ++k) {
      const Eigen::Vector3d a = mu.values().head<3>();
      stamp.at<cv::Vec3f>(j, k) = cv::Vec3f(float(a.x() * (j + 1) + t * a.y()), float(a.y() * k - a.z()), float(a.z() * (j - k) + a.x()));
    }
  return stamp;
}

struct Set {
  std::vector<MomentList> rho, mu;
  std::vector<cv::Mat> stamps;
};

Set sameSiteSet(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g;
  Set s;
  for (int i = 0; i < n; ++i) {
    s.rho.push_back(site(0.0));
    s.mu.push_back(deformation(Eigen::Vector3d(g(rng), g(rng), g(rng))));
    s.stamps.push_back(linearStamp(s.mu.back(), 0.0));
  }
  return s;
}

cv::Mat blend(const std::vector<cv::Mat>& stamps, const Eigen::VectorXd& w) {
  cv::Mat out(stamps[0].size(), CV_32FC3, cv::Scalar::all(0));
  for (std::size_t i = 0; i < stamps.size(); ++i) cv::scaleAdd(stamps[i], w[static_cast<Eigen::Index>(i)], out, out);
  return out;
}

}  // namespace

TEST(StampRegression, RecoversAStampLinearInMuForANewDeformation) {
  const Set s = sameSiteSet(8, 1);
  const en::StampRegression regression(s.rho, s.mu, en::stampGramMatrix(s.stamps));
  EXPECT_LT(regression.fit().looError, 0.05);
  const MomentList query = deformation(Eigen::Vector3d(2.0, -1.5, 0.7));  // outside the examples' spread
  Eigen::VectorXd w;
  double confidence = 0.0;
  regression.weights(site(0.0), query, w, confidence);
  const cv::Mat predicted = blend(s.stamps, w), truth = linearStamp(query, 0.0);
  EXPECT_LT(cv::norm(predicted, truth, cv::NORM_L2), 0.05 * cv::norm(truth, cv::NORM_L2));
  EXPECT_GT(confidence, 0.9);
  // No deformation, no detail.
  regression.weights(site(0.0), deformation(Eigen::Vector3d::Zero()), w, confidence);
  EXPECT_EQ(w.cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(confidence, 0.0);
}

TEST(StampRegression, ClosedFormLeaveOneOutEqualsRefittingWithoutEachExample) {
  Set s = sameSiteSet(6, 2);
  for (int i = 0; i < 4; ++i) {  // a second site, its own field
    s.rho.push_back(site(0.8));
    s.mu.push_back(deformation(Eigen::Vector3d(0.3 * i, 1.0 - 0.2 * i, 0.5)));
    cv::Mat stamp = linearStamp(s.mu.back(), 0.8);
    stamp += cv::Scalar(0.3 * i * i, 0.0, -0.1 * i);  // not linear in mu: a leave-one-out error well above round-off
    s.stamps.push_back(stamp);
  }
  const Eigen::MatrixXd G = en::stampGramMatrix(s.stamps);
  const en::StampRegression regression(s.rho, s.mu, G);
  const double sigma = regression.fit().sigmaRho;
  const Eigen::Index n = static_cast<Eigen::Index>(s.rho.size());
  // The kernel of the header, written out: exp(-d_rho^2 / (2 sigma^2)) <mu, mu'> (multiplicities 1 at order <= 1).
  Eigen::MatrixXd K(n, n);
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = 0; j < n; ++j) {
      const double d = (s.rho[i].values() - s.rho[j].values()).norm();
      K(i, j) = std::exp(-d * d / (2 * sigma * sigma)) * s.mu[i].values().dot(s.mu[j].values());
    }
  const double lambda = regression.fit().epsilon * K.diagonal().mean();
  double residual = 0.0, signal = 0.0;
  for (Eigen::Index out = 0; out < n; ++out) {
    std::vector<Eigen::Index> keep;
    for (Eigen::Index i = 0; i < n; ++i)
      if (i != out) keep.push_back(i);
    Eigen::MatrixXd A = K(keep, keep);
    A.diagonal().array() += lambda;
    const Eigen::VectorXd w = A.ldlt().solve(K(keep, out));
    std::vector<cv::Mat> others;
    for (Eigen::Index i : keep) others.push_back(s.stamps[static_cast<std::size_t>(i)]);
    const double e = cv::norm(blend(others, w), s.stamps[static_cast<std::size_t>(out)], cv::NORM_L2);
    residual += e * e;
    signal += G(out, out);
  }
  EXPECT_GT(residual / signal, 1e-3);
  EXPECT_NEAR(regression.fit().looError, residual / signal, 1e-5 * residual / signal);
  EXPECT_GT(regression.fit().gain, 0.0);
  EXPECT_LE(regression.fit().gain, 1.0);
  EXPECT_LE(regression.fit().gainedError, regression.fit().looError * (1 + 1e-12));
}

TEST(StampRegression, DetailFadesFarFromEverySite) {
  const Set s = sameSiteSet(6, 3);
  const en::StampRegression regression(s.rho, s.mu, en::stampGramMatrix(s.stamps));
  Eigen::VectorXd w;
  double confidence = 1.0;
  regression.weights(site(1e3), deformation(Eigen::Vector3d(1, 0, 0)), w, confidence);
  EXPECT_LT(confidence, 1e-12);
  EXPECT_LT(w.cwiseAbs().maxCoeff(), 1e-12);
}

TEST(StampRegression, BadInputThrows) {
  const Set s = sameSiteSet(3, 4);
  const Eigen::MatrixXd G = en::stampGramMatrix(s.stamps);
  EXPECT_THROW(en::StampRegression({s.rho[0]}, {s.mu[0]}, G.topLeftCorner(1, 1)), de::InvalidInputError);
  EXPECT_THROW(en::StampRegression(s.rho, s.mu, G.topLeftCorner(2, 2)), de::InvalidInputError);
  EXPECT_THROW(en::StampRegression(s.rho, s.mu, Eigen::MatrixXd::Zero(3, 3)), de::InvalidInputError);
  const std::vector<MomentList> still(3, deformation(Eigen::Vector3d::Zero()));
  EXPECT_THROW(en::StampRegression(s.rho, still, G), de::InvalidInputError);
  const en::StampRegression regression(s.rho, s.mu, G);
  Eigen::VectorXd w;
  double confidence = 0.0;
  MomentList nan = s.mu[0];
  nan.values()[0] = std::nan("");
  EXPECT_THROW(regression.weights(s.rho[0], nan, w, confidence), de::InvalidInputError);
  EXPECT_THROW(regression.weights(s.rho[0], MomentList(1, 2, 3), w, confidence), de::InvalidInputError);  // layout
  EXPECT_EQ(en::parseBlendMethod("paper"), en::BlendMethod::Paper);
  EXPECT_EQ(en::parseBlendMethod("regression"), en::BlendMethod::Regression);
  EXPECT_THROW(en::parseBlendMethod("kriging"), de::InvalidInputError);
}
