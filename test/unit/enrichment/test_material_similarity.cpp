// Material similarity of two scenes: 1 for equal materials, exp(-1/2) at a factor of 1.5 in every entry,
// symmetric, and a missing skin counts as the bulk's modulus.
#include <gtest/gtest.h>

#include <cmath>

#include "deformation_enrichment/enrichment/material_similarity.hpp"

using namespace deformation_enrichment;

namespace {
scene_file::SceneDescription tissue(double bulk, double skin, double thickness) {
  scene_file::SceneDescription s;
  s.material = {bulk, 0.45};
  if (skin > 0.0) s.skin = scene_file::Skin{thickness, {skin, 0.3}};
  return s;
}
}  // namespace

TEST(MaterialSimilarity, OneForTheSameTissueFallingWithLogRatios) {
  const auto slab = tissue(1e4, 1e6, 0.001);
  EXPECT_DOUBLE_EQ(enrichment::materialSimilarity(slab, slab), 1.0);
  const auto scaled = tissue(1.5e4, 1.5e6, 0.0015);
  EXPECT_NEAR(enrichment::materialSimilarity(slab, scaled), std::exp(-0.5), 1e-12);
  EXPECT_NEAR(enrichment::materialSimilarity(scaled, slab), std::exp(-0.5), 1e-12);
  // Without skins only the bulk counts, twice (bulk and "skin" = bulk).
  EXPECT_NEAR(enrichment::materialSimilarity(tissue(1e4, 0, 0), tissue(1.5e4, 0, 0)), std::exp(-0.5), 1e-12);
  // The slab against the liver scene (5 kPa bulk, 200 kPa skin of 0.8 mm): detail nearly off.
  EXPECT_LT(enrichment::materialSimilarity(slab, tissue(5e3, 2e5, 0.0008)), 0.1);
}
