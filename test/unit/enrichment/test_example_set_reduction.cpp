// Reduced example sets: re-sampled stamps reproduce affine fields exactly at every resolution (bilinear
// look-up does), and truncated Hermite orders keep exactly the lower-order moments.
#include <gtest/gtest.h>

#include "deformation_enrichment/enrichment/example_set_reduction.hpp"
#include "deformation_enrichment/enrichment/stamp.hpp"
#include "deformation_enrichment/error.hpp"

namespace de = deformation_enrichment;
namespace en = deformation_enrichment::enrichment;
namespace ex = deformation_enrichment::examples;
using de::hermite::MomentList;

namespace {

constexpr double kRadius = 0.02;

// Affine displacement field (frame coordinates) at stamp coordinates (phi, varphi).
Eigen::Vector3d affine(double phi, double varphi) {
  return Eigen::Vector3d(0.001 + 0.03 * phi - 0.01 * varphi, -0.002 + 0.02 * varphi, 0.0005 + 0.05 * phi + 0.04 * varphi);
}

ex::ExampleSet affineSet(int resolution) {
  ex::Example e;
  e.rho = MomentList(0, 3, 1);
  e.rho.values().setLinSpaced(0.1, 2.0);
  e.mu = MomentList(1, 2, 3);
  e.mu.values().setLinSpaced(-1.0, 1.0);
  e.stampRadius = kRadius;
  e.stamp.create(resolution, resolution, CV_32FC3);
  const double spacing = 2.0 * kRadius / (resolution - 1);
  for (int row = 0; row < resolution; ++row)
    for (int col = 0; col < resolution; ++col) {
      const Eigen::Vector3d v = affine(-kRadius + col * spacing, -kRadius + row * spacing);
      e.stamp.at<cv::Vec3f>(row, col) = cv::Vec3f(float(v.x()), float(v.y()), float(v.z()));
    }
  ex::ExampleSet set;
  set.examples = {e, e};
  return set;
}

}  // namespace

TEST(ExampleSetReduction, ResampledStampsReproduceAffineFields) {
  const ex::ExampleSet set = affineSet(64);
  for (int n : {2, 8, 17, 64, 100}) {
    const ex::ExampleSet reduced = en::withStampResolution(set, n);
    ASSERT_EQ(reduced.examples.size(), 2u);
    const cv::Mat& stamp = reduced.examples[0].stamp;
    ASSERT_EQ(stamp.rows, n);
    ASSERT_EQ(stamp.cols, n);
    ASSERT_EQ(stamp.type(), CV_32FC3);
    // Look-ups anywhere in the square agree with the field to float precision.
    for (double phi : {-kRadius, -0.013, 0.0, 0.007, kRadius})
      for (double varphi : {-kRadius, -0.004, 0.011, kRadius})
        EXPECT_LT((en::sampleStamp(stamp, kRadius, phi, varphi) - affine(phi, varphi)).norm(), 1e-6) << n << " nodes at " << phi << ", " << varphi;
    EXPECT_EQ(reduced.examples[0].rho.values(), set.examples[0].rho.values());  // descriptors untouched
  }
  EXPECT_THROW(en::withStampResolution(set, 1), de::InvalidInputError);
}

TEST(ExampleSetReduction, LowerHermiteOrdersKeepTheLowerMoments) {
  const ex::ExampleSet set = affineSet(8);
  const ex::ExampleSet reduced = en::withHermiteOrders(set, 1, 1);
  const ex::Example& full = set.examples[0];
  const ex::Example& cut = reduced.examples[0];
  EXPECT_EQ(cut.rho.firstOrder(), 0);
  EXPECT_EQ(cut.rho.lastOrder(), 1);
  EXPECT_EQ(cut.mu.lastOrder(), 1);
  EXPECT_EQ(cut.mu.channels(), 3);
  for (int n = 0; n <= 1; ++n) EXPECT_EQ(cut.rho.order(n), full.rho.order(n));
  for (int c = 0; c < 3; ++c) EXPECT_EQ(cut.mu.order(1, c), full.mu.order(1, c));
  EXPECT_EQ(cut.rho.values().size(), 4);  // 1 + 3 components
  EXPECT_EQ(cut.mu.values().size(), 9);   // 3 channels x 3 components
  const ex::ExampleSet same = en::withHermiteOrders(set, 3, 2);
  EXPECT_EQ(same.examples[0].mu.values(), full.mu.values());
  EXPECT_THROW(en::withHermiteOrders(set, 4, 2), de::InvalidInputError);  // not stored
  EXPECT_THROW(en::withHermiteOrders(set, 3, 0), de::InvalidInputError);  // mu starts at order 1
}
