// The penalty tool's footprint integral: resolution-independent total stiffness (k pi R^2 / 3), a load
// that varies continuously as the tool moves across a coarse mesh, and clear errors.
#include <gtest/gtest.h>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/scenes/procedural_scene.hpp"
#include "deformation_enrichment/acquisition/tool_loading.hpp"

using namespace deformation_enrichment;

namespace {

scenes::Scene slab(int cells) {
  scenes::SlabOptions o;
  o.layering = scenes::Layering{Eigen::Vector3i(cells, cells, 2), 0.001, 1};
  return scenes::makeSlab(o);
}

double stiffnessOf(const elasticity::AnchorSprings& s, int vertex) {
  for (std::size_t i = 0; i < s.vertices.size(); ++i)
    if (s.vertices[i] == vertex) return s.stiffness[static_cast<Eigen::Index>(i)];
  return 0.0;
}

}  // namespace

TEST(ToolSprings, TotalStiffnessIsTheFootprintIntegralAtAnyResolution) {
  const double R = 0.005, k = 1e9, exact = k * M_PI * R * R / 3.0;
  for (int cells : {10, 24, 40}) {
    const scenes::Scene scene = slab(cells);
    for (const Eigen::Vector3d& centre : {Eigen::Vector3d(0.0, 0.0, 0.02), Eigen::Vector3d(0.0137, -0.0042, 0.02)}) {
      const elasticity::AnchorSprings s = acquisition::toolSprings(scene, centre, R, k);
      s.validate(scene.mesh.numVertices());
      EXPECT_NEAR(s.stiffness.sum(), exact, 0.01 * exact) << cells << " cells";
      for (std::size_t i = 0; i < s.vertices.size(); ++i) {
        EXPECT_TRUE(s.targets.col(static_cast<Eigen::Index>(i)).isApprox(scene.mesh.vertices.col(s.vertices[i])));
        EXPECT_NEAR(scene.mesh.vertices(2, s.vertices[i]), 0.02, 1e-12);  // top vertices only
      }
    }
  }
}

TEST(ToolSprings, LoadVariesContinuouslyAcrossACoarseCell) {
  // 1 cm cells, 5 mm tool: a Dirichlet footprint switches vertices on and off as the tool moves; the
  // penalty stiffness of every vertex changes by a small amount per 0.1 mm step.
  const scenes::Scene scene = slab(10);
  const double R = 0.005, k = 1e9, total = k * M_PI * R * R / 3.0;
  elasticity::AnchorSprings previous = acquisition::toolSprings(scene, Eigen::Vector3d(0.0, 0.0, 0.02), R, k);
  for (int step = 1; step <= 100; ++step) {
    const elasticity::AnchorSprings current = acquisition::toolSprings(scene, Eigen::Vector3d(1e-4 * step, 0.0, 0.02), R, k);
    double change = 0.0;
    for (int v : scene.topVertices) change = std::max(change, std::abs(stiffnessOf(current, v) - stiffnessOf(previous, v)));
    EXPECT_LT(change, 0.03 * total) << "at x = " << 1e-4 * step;
    previous = current;
  }
}

TEST(ToolSprings, RejectsAToolAwayFromTheTopAndBadParameters) {
  const scenes::Scene scene = slab(10);
  EXPECT_THROW(acquisition::toolSprings(scene, Eigen::Vector3d(0.3, 0.0, 0.02), 0.005, 1e9), InvalidInputError);
  EXPECT_THROW(acquisition::toolSprings(scene, Eigen::Vector3d(0.0, 0.0, 0.02), 0.0, 1e9), InvalidInputError);
  EXPECT_THROW(acquisition::toolSprings(scene, Eigen::Vector3d(0.0, 0.0, 0.02), 0.005, -1.0), InvalidInputError);
  EXPECT_THROW(acquisition::toolSprings(scene, Eigen::Vector3d(std::nan(""), 0.0, 0.02), 0.005, 1e9), InvalidInputError);
}
