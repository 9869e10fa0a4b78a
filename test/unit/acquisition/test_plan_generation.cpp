#include <gtest/gtest.h>

#include <filesystem>
#include <unistd.h>

#include "deformation_enrichment/acquisition/plan_generation.hpp"
#include "deformation_enrichment/examples/example_set_io.hpp"
#include "deformation_enrichment/error.hpp"
#include "tiny_slab.hpp"

using namespace deformation_enrichment;

namespace {

// The small test slab with 8-node stamps.
scene_file::SceneDescription smallSlab() {
  scene_file::SceneDescription d = de_test::tinySlab();
  d.stamp.resolution = 8;
  return d;
}

bool sameEntry(const acquisition::PlanEntry& a, const acquisition::PlanEntry& b) {
  return a.point == b.point && a.depth == b.depth && a.drag == b.drag;
}

}  // namespace

TEST(AutoPlan, IsNestedSpreadAndWithinTheInteractionRange) {
  acquisition::SceneAcquisition acq(smallSlab());
  const auto small = acquisition::autoPlan(acq, 5), large = acquisition::autoPlan(acq, 16);
  ASSERT_EQ(small.size(), 5u);
  ASSERT_EQ(large.size(), 16u);
  for (std::size_t i = 0; i < small.size(); ++i) EXPECT_TRUE(sameEntry(small[i], large[i])) << "entry " << i;
  const double r = acq.scene().tool.radius;
  double closest = INFINITY;
  for (std::size_t i = 0; i < large.size(); ++i) {
    EXPECT_NO_THROW(acq.toolPath(large[i]));  // touchable, off the support
    EXPECT_GE(large[i].depth, 0.3 * r);
    EXPECT_LE(large[i].depth, 0.9 * r);
    const double drag = large[i].drag.norm();
    if (i % 2 == 0) EXPECT_EQ(drag, 0.0) << "entry " << i;
    else EXPECT_TRUE(drag >= 0.2 * r * (1 - 1e-12) && drag <= r * (1 + 1e-12)) << "entry " << i << ": drag " << drag;
    for (std::size_t j = 0; j < i; ++j) closest = std::min(closest, (large[i].point - large[j].point).norm());
  }
  EXPECT_GT(closest, 0.0);  // farthest-point order never repeats a site
  // Depths spread over their range (a Halton sequence, not one value).
  double lo = INFINITY, hi = 0.0;
  for (const auto& e : large) lo = std::min(lo, e.depth), hi = std::max(hi, e.depth);
  EXPECT_GT(hi - lo, 0.4 * r);
  EXPECT_THROW(acquisition::autoPlan(acq, 0), InvalidInputError);
  EXPECT_THROW(acquisition::autoPlan(acq, 100000), InvalidInputError);
}

TEST(AutoPlan, ASmallerSetIsThePrefixOfALargerOneByteForByte) {
  acquisition::SceneAcquisition acq(smallSlab());
  const std::string base = "/tmp/de_nested_" + std::to_string(::getpid());
  std::filesystem::remove_all(base);
  const auto small = acq.acquireSet(acquisition::autoPlan(acq, 2), base + "_2");
  const auto large = acq.acquireSet(acquisition::autoPlan(acq, 3), base + "_3");
  ASSERT_EQ(small.examples.size(), 2u);
  ASSERT_EQ(large.examples.size(), 3u);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(cv::norm(small.examples[i].stamp, large.examples[i].stamp, cv::NORM_INF), 0.0);
    EXPECT_EQ(small.examples[i].mu.values(), large.examples[i].mu.values());
    EXPECT_EQ(small.examples[i].rho.values(), large.examples[i].rho.values());
  }
  std::filesystem::remove_all(base + "_2");
  std::filesystem::remove_all(base + "_3");
}

TEST(RandomContacts, AreSeededAndTouchable) {
  const acquisition::SceneAcquisition acq(smallSlab());
  const auto a = acquisition::randomContacts(acq, 6, 7), b = acquisition::randomContacts(acq, 6, 7);
  const auto c = acquisition::randomContacts(acq, 6, 8);
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_TRUE(sameEntry(a[i], b[i]));
    EXPECT_NO_THROW(acq.toolPath(a[i]));
  }
  EXPECT_FALSE(sameEntry(a[0], c[0]));
}
