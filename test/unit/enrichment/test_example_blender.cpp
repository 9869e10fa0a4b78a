// The load-time chain: fitted widths, eq. (15) -> RBF -> eq. (16) reproduces an example's stamp at its
// own descriptors and fades far from every example.
#include <gtest/gtest.h>

#include <cmath>

#include "deformation_enrichment/enrichment/example_blender.hpp"
#include "deformation_enrichment/error.hpp"

namespace de = deformation_enrichment;
namespace en = deformation_enrichment::enrichment;
namespace ex = deformation_enrichment::examples;
using de::hermite::MomentList;

namespace {

ex::Example example(double t, double theta) {
  ex::Example e;
  e.rho = MomentList(0, 1, 1);
  e.rho.values().setZero();
  e.rho.values()[0] = t;
  e.mu = MomentList(1, 1, 3);
  e.mu.values().setZero();
  e.mu.values()[0] = std::cos(theta);
  e.mu.values()[1] = std::sin(theta);
  e.stamp.create(12, 12, CV_32FC3);
  for (int j = 0; j < 12; ++j)
    for (int k = 0; k < 12; ++k)
      e.stamp.at<cv::Vec3f>(j, k) = cv::Vec3f(float(std::sin(0.4 * k + t)), float(std::cos(0.3 * j + theta)), float(1e-3 * (j + k) * t));
  e.stampRadius = 0.01;
  return e;
}

ex::ExampleSet exampleSet() {
  ex::ExampleSet set;
  for (int a = 0; a < 5; ++a)
    for (int b = 0; b < 4; ++b) set.examples.push_back(example(0.5 * a, 0.3 * b));
  return set;
}

}  // namespace

TEST(ExampleBlender, FitsWidthsAtLoadAndReproducesExamples) {
  const ex::ExampleSet set = exampleSet();
  const en::ExampleBlender blender(set);
  ASSERT_TRUE(blender.fit().has_value());
  EXPECT_EQ(blender.widths().sigmaRho, blender.fit()->best.sigmaRho);
  EXPECT_EQ(blender.widths().sigmaU, blender.fit()->best.sigmaU);
  EXPECT_DOUBLE_EQ(blender.stampRadius(), 0.01);
  en::BlendResult out;
  for (std::size_t i = 0; i < set.examples.size(); ++i) {
    blender.blend(set.examples[i].rho, set.examples[i].mu, out);
    EXPECT_NEAR(out.rbf.confidence, 1.0, 1e-12);
    // Interpolation up to the regularisation: the blended stamp is the example's own.
    EXPECT_LT(cv::norm(out.stamp, set.examples[i].stamp, cv::NORM_INF), 0.02 * cv::norm(set.examples[i].stamp, cv::NORM_INF)) << i;
  }
}

TEST(ExampleBlender, DetailFadesFarFromEveryExample) {
  const en::ExampleBlender blender(exampleSet());
  const ex::Example far = example(40.0, 0.3);
  en::BlendResult out;
  blender.blend(far.rho, far.mu, out);
  EXPECT_LT(out.rbf.confidence, 1e-10);
  EXPECT_LT(cv::norm(out.stamp, cv::NORM_INF), 1e-8);
}

TEST(ExampleBlender, FixedWidthsSingleExampleAndReconfiguration) {
  en::ExampleBlenderOptions options;
  options.fitWidths = false;
  options.widths = {0.4, 0.2};
  en::ExampleBlender blender(exampleSet(), options);
  EXPECT_FALSE(blender.fit().has_value());
  EXPECT_EQ(blender.widths().sigmaRho, 0.4);
  blender.setWidths({0.7, 0.3});
  EXPECT_EQ(blender.widths().sigmaU, 0.3);
  EXPECT_THROW(blender.setWidths({0.0, 0.3}), de::InvalidInputError);
  EXPECT_EQ(blender.widths().sigmaRho, 0.7);  // a rejected reconfiguration keeps the previous widths

  ex::ExampleSet one;
  one.examples.push_back(example(0.0, 0.0));
  const en::ExampleBlender single(one);  // no leave-one-out with one example
  EXPECT_FALSE(single.fit().has_value());
  en::BlendResult out;
  single.blend(one.examples[0].rho, one.examples[0].mu, out);
  EXPECT_LT(cv::norm(out.stamp, one.examples[0].stamp, cv::NORM_INF), 1e-5);
}

TEST(ExampleBlender, BadSetsThrow) {
  EXPECT_THROW(en::ExampleBlender{ex::ExampleSet{}}, de::InvalidInputError);
  ex::ExampleSet set = exampleSet();
  set.examples[3].stampRadius = 0.02;
  EXPECT_THROW(en::ExampleBlender{set}, de::InvalidInputError);
  set = exampleSet();
  set.examples[2].rho = MomentList(0, 2, 1);
  EXPECT_THROW(en::ExampleBlender{set}, de::InvalidInputError);
  set = exampleSet();
  set.examples[1].frame(0, 0) = 2.0;
  EXPECT_THROW(en::ExampleBlender{set}, de::InvalidInputError);
}
