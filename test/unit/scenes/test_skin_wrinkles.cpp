// A tool dragged laterally across a slab with a stiff thin skin wrinkles the surface ahead of it; the
// same mesh without the skin only bulges. Measure: along the top centreline ahead of the tool, the number
// of ridges, i.e. local maxima of the height z(x) that rise at least kProminence above the lowest point
// between them and the previous ridge (hysteresis peak counting, robust to round-off ripples).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>

#include "deformation_enrichment/elasticity/quasi_static_solver.hpp"
#include "deformation_enrichment/scenes/procedural_scene.hpp"
#include "deformation_enrichment/acquisition/tool_loading.hpp"

using namespace deformation_enrichment;

namespace {

constexpr double kProminence = 5e-5;  // 50 micrometres

struct DragOutcome {
  int ridges = 0;
  bool converged = true;
  std::vector<std::pair<double, double>> profile;  // (deformed x, z) ahead of the tool
};

/// Peaks of z separated by dips of at least `prominence`: a peak counts once z has risen that far above
/// the preceding dip and then fallen that far below the peak again.
int countRidges(const std::vector<std::pair<double, double>>& profile, double prominence) {
  int ridges = 0;
  double low = profile.front().second, high = low;
  bool rising = true;
  for (const auto& point : profile) {
    const double z = point.second;
    if (rising) {
      high = std::max(high, z);
      if (high - z >= prominence && high - low >= prominence) {
        ++ridges;
        rising = false;
        low = z;
      }
      if (high - z >= prominence && high - low < prominence) low = high = z;
      low = std::min(low, z);
    } else {
      low = std::min(low, z);
      if (z - low >= prominence) {
        rising = true;
        high = z;
      }
    }
  }
  return ridges;
}

DragOutcome dragAcrossStrip(bool withSkin) {
  scenes::SlabOptions options;
  options.lo = Eigen::Vector3d(-0.05, -0.01, 0.0);
  options.hi = Eigen::Vector3d(0.05, 0.01, 0.02);
  options.layering.cells = Eigen::Vector3i(40, 4, 5);
  options.layering.skinThickness = 0.0005;
  options.layering.skinLayers = 1;
  scenes::Scene scene = scenes::makeSlab(options);
  // Same mesh for both runs; only the skin's material differs (stiff skin vs bulk material).
  const auto bulk = elasticity::lameFromYoungPoisson(1e4, 0.45);
  const auto skin = withSkin ? elasticity::lameFromYoungPoisson(1e6, 0.3) : bulk;
  const elasticity::TetFem fem(scene.mesh,
                               {elasticity::StableNeoHookean(bulk.mu, bulk.lambda), elasticity::StableNeoHookean(skin.mu, skin.lambda)},
                               scene.materialId);
  // The tissue continues beyond the strip's ends: hold the end faces x = +-0.05 as well as the bottom.
  for (Eigen::Index v = 0; v < scene.mesh.numVertices(); ++v)
    if (std::abs(std::abs(scene.mesh.vertices(0, v)) - 0.05) < 1e-12 && scene.mesh.vertices(2, v) > 0.0)
      scene.fixedVertices.push_back(static_cast<int>(v));
  const Eigen::Vector2d toolAt(-0.025, 0.0);
  const double toolRadius = 0.0035;
  std::vector<int> tool = acquisition::toolFootprint(scene, toolAt, toolRadius);
  elasticity::QuasiStaticSolver solver(fem);
  Eigen::Matrix3Xd x = scene.mesh.vertices;
  DragOutcome outcome;
  const int indentSteps = 1, dragSteps = 8;
  for (int step = 1; step <= indentSteps + dragSteps; ++step) {
    const Eigen::Vector3d d = acquisition::toolDisplacement(step, indentSteps, dragSteps, -Eigen::Vector3d::UnitZ(), 0.002,
                                                       Eigen::Vector3d::UnitX(), 0.02);
    const elasticity::SolveResult result = solver.solve(x, acquisition::toolConstraints(scene, tool, d));
    outcome.converged = outcome.converged && result.converged();
    EXPECT_TRUE(result.converged()) << (withSkin ? "skin " : "no skin ") << step << ": " << result.message;
    if (std::getenv("DE_DEBUG_HISTORY"))
      for (const auto& r : result.history) std::printf("  it %d E %.9g f %.3e a %.3g ls %d exact %d reg %.2g\n", r.iteration, r.energy, r.forceNorm, r.stepLength, r.lineSearchSteps, r.exactHessian, r.regularisation);
  }
  std::vector<int> line;
  for (int v : scene.topVertices)
    if (std::abs(scene.mesh.vertices(1, v)) < 1e-12 && scene.mesh.vertices(0, v) > toolAt.x() + toolRadius) line.push_back(v);
  std::sort(line.begin(), line.end(), [&](int a, int b) { return scene.mesh.vertices(0, a) < scene.mesh.vertices(0, b); });
  for (int v : line)
    if (x(0, v) > toolAt.x() + 0.02 + toolRadius) outcome.profile.emplace_back(x(0, v), x(2, v));
  outcome.ridges = countRidges(outcome.profile, kProminence);
  return outcome;
}

}  // namespace

TEST(SkinWrinkles, RidgeCounterOnSyntheticProfiles) {
  std::vector<std::pair<double, double>> flat, bump, wavy, noisy;
  for (int i = 0; i <= 100; ++i) {
    const double s = i / 100.0;
    flat.emplace_back(s, 0.02);
    bump.emplace_back(s, 0.02 + 1e-3 * std::exp(-50 * (s - 0.5) * (s - 0.5)));
    wavy.emplace_back(s, 0.02 + 2e-4 * std::sin(2 * M_PI * 4 * s));
    noisy.emplace_back(s, 0.02 + 1e-5 * ((i % 2) ? 1 : -1));
  }
  EXPECT_EQ(countRidges(flat, kProminence), 0);
  EXPECT_EQ(countRidges(bump, kProminence), 1);
  EXPECT_EQ(countRidges(wavy, kProminence), 4);
  EXPECT_EQ(countRidges(noisy, kProminence), 0);
}

TEST(SkinWrinkles, StiffSkinWrinklesWhereBareBulkOnlyBulges) {
  const DragOutcome skin = dragAcrossStrip(true);
  const DragOutcome bare = dragAcrossStrip(false);
  if (std::getenv("DE_DEBUG_HISTORY")) {
    for (const auto& p : skin.profile) std::printf("skin  x %.4f z %.6f\n", p.first, p.second);
    for (const auto& p : bare.profile) std::printf("bare  x %.4f z %.6f\n", p.first, p.second);
  }
  std::printf("ridges ahead of the tool: skin %d, no skin %d\n", skin.ridges, bare.ridges);
  EXPECT_TRUE(skin.converged && bare.converged);
  EXPECT_GE(skin.ridges, 2);
  EXPECT_LE(bare.ridges, 1);
}
