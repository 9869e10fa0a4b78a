#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "../expect_error.hpp"
#include "deformation_enrichment/bullet_engine/bullet_tissue.hpp"
#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/scene_file/scene_description.hpp"
#include "deformation_enrichment/scenes/scene_models.hpp"

using namespace deformation_enrichment;
using bullet_engine::BulletTissue;
using bullet_engine::BulletTissueOptions;

namespace {

constexpr double kDepth = 0.003;         // indentation (m)
constexpr double kSettledSpeed = 1e-4;   // m/s
constexpr int kMaxSettleSteps = 2000;    // ~0.5 s of simulated time; the slab settles in ~560 steps

// The scene's material and tool, with the mesh's stable step (as the node's defaults).
BulletTissueOptions tissueOptions(const scene_file::SceneDescription& scene, const mesh::TetMesh& coarse) {
  BulletTissueOptions o;
  o.young = scene.material.young;
  o.poisson = scene.material.poisson;
  o.toolRadius = scene.tool.radius;
  o.timeStep = bullet_engine::stableTimeStep(coarse, o.young, o.poisson, o.density);
  return o;
}

struct Slab {
  scene_file::SceneDescription scene = scene_file::readSceneFile(scene_file::findSceneFile("slab"));
  scenes::Scene coarse = scenes::buildSceneModels(scene).coarse;

  BulletTissueOptions options() const { return tissueOptions(scene, coarse.mesh); }
  // The top contact point at the centre of the slab and the top node nearest it.
  Eigen::Vector3d contact() const { return Eigen::Vector3d(0.0, 0.0, coarse.mesh.vertices.row(2).maxCoeff()); }
  Eigen::Index nodeNearest(const Eigen::Vector3d& p) const {
    Eigen::Index nearest = 0;
    (coarse.mesh.vertices.colwise() - p).colwise().norm().minCoeff(&nearest);
    return nearest;
  }
  // The sphere's centre that indents the top `depth` at the contact: outward normal +z.
  Eigen::Vector3d indentingCentre(double depth) const { return contact() + (scene.tool.radius - depth) * Eigen::Vector3d::UnitZ(); }
};

const Slab& slab() {
  static const Slab s;
  return s;
}

// Steps until the tool has reached `centre` and no node moves faster than `speed`; the steps taken.
int settle(BulletTissue& tissue, const Eigen::Vector3d& centre, double speed, int maxSteps) {
  for (int step = 1; step <= maxSteps; ++step) {
    EXPECT_TRUE(tissue.step());
    if (tissue.toolCentre() == centre && tissue.largestSpeed() < speed) return step;
  }
  return maxSteps + 1;
}

double largestDeviation(const Eigen::Matrix3Xd& a, const Eigen::Matrix3Xd& b) { return (a - b).colwise().norm().maxCoeff(); }

}  // namespace

TEST(BulletTissue, AToolClearOfTheBodyLeavesTheTissueAtRest) {
  const Slab& s = slab();
  BulletTissue tissue(s.coarse.mesh, s.coarse.fixedVertices, s.options());
  EXPECT_TRUE(tissue.step(200));  // parked: the step is skipped
  EXPECT_EQ(tissue.positions(), s.coarse.mesh.vertices);
  // Hovering a millimetre above the top: Bullet steps, and nothing moves.
  const Eigen::Vector3d above = s.indentingCentre(-0.001);
  tissue.setToolCentre(above);
  ASSERT_LE(settle(tissue, above, kSettledSpeed, kMaxSettleSteps), kMaxSettleSteps);
  EXPECT_TRUE(tissue.step(200));
  EXPECT_LE(largestDeviation(tissue.positions(), s.coarse.mesh.vertices), 1e-9);
  EXPECT_EQ(tissue.divergences(), 0);
}

// A command under the body, clear of it: the parked tool enters below the bottom face nearest the command and
// touches nothing; from the park position above it would have swept through the slab.
TEST(BulletTissue, AParkedToolComesInFromTheSideOfItsCommand) {
  const Slab& s = slab();
  BulletTissue tissue(s.coarse.mesh, s.coarse.fixedVertices, s.options());
  const double bottom = s.coarse.mesh.vertices.row(2).minCoeff();
  const Eigen::Vector3d under(0.0, 0.0, bottom - 2.0 * s.scene.tool.radius);
  tissue.setToolCentre(under);
  EXPECT_LT(tissue.toolCentre().z(), bottom) << "the tool must start below the body";
  ASSERT_LE(settle(tissue, under, kSettledSpeed, kMaxSettleSteps), kMaxSettleSteps);
  EXPECT_LE(largestDeviation(tissue.positions(), s.coarse.mesh.vertices), 1e-9);
  EXPECT_EQ(tissue.divergences(), 0);
}

// The node under the contact goes down with the sphere, at least half the indentation (a tool that passed
// through the surface would leave it near 0), and at most half a millimetre past it: the sphere rests on the
// 1 cm faces around the node, tangent to them, so the node sits below the sphere's lowest point (0.36 mm
// measured).
TEST(BulletTissue, AThreeMillimetreIndentationSettlesWhereTheToolPushedIt) {
  const Slab& s = slab();
  BulletTissue tissue(s.coarse.mesh, s.coarse.fixedVertices, s.options());
  const Eigen::Vector3d centre = s.indentingCentre(kDepth);
  tissue.setToolCentre(centre);
  const int steps = settle(tissue, centre, kSettledSpeed, kMaxSettleSteps);
  EXPECT_LE(steps, kMaxSettleSteps);

  const Eigen::Matrix3Xd x = tissue.positions();
  ASSERT_TRUE(x.allFinite());
  for (int v : s.coarse.fixedVertices) EXPECT_EQ(x.col(v), s.coarse.mesh.vertices.col(v)) << "fixed node " << v;  // zero mass: held exactly
  // Contacts are on the faces with a 0.01 mm margin; no node may be inside the sphere by more than 0.05 mm.
  const double inside = s.scene.tool.radius - (x.colwise() - centre).colwise().norm().minCoeff();
  EXPECT_LE(inside, 5e-5);
  const Eigen::Index node = s.nodeNearest(s.contact());
  const double down = s.coarse.mesh.vertices(2, node) - x(2, node);
  EXPECT_GE(down, 0.0015);
  EXPECT_LE(down, 0.0035);
  EXPECT_EQ(tissue.divergences(), 0);
}

// Where the surface bends (a corner, the middle of an edge) and between nodes, 1 cm apart, wider than the
// tool: each 3 mm press settles without Bullet blowing up, and the tool does not pass through the surface
// (some node goes down by at least half the indentation). Velocity-projection contacts blew up at the
// corner and the edge within ten steps of touching.
TEST(BulletTissue, PressesAtACornerAnEdgeAndBetweenNodesSettle) {
  const Slab& s = slab();
  const double half = 0.05;  // the slab's half width (m)
  for (const Eigen::Vector2d& at : {Eigen::Vector2d(-half, -half), Eigen::Vector2d(0.0, -half), Eigen::Vector2d(0.005, 0.005)}) {
    SCOPED_TRACE("press at (" + std::to_string(at.x()) + ", " + std::to_string(at.y()) + ")");
    BulletTissue tissue(s.coarse.mesh, s.coarse.fixedVertices, s.options());
    const Eigen::Vector3d centre = s.indentingCentre(kDepth) + Eigen::Vector3d(at.x(), at.y(), 0.0);
    tissue.setToolCentre(centre);
    EXPECT_LE(settle(tissue, centre, kSettledSpeed, kMaxSettleSteps), kMaxSettleSteps);
    EXPECT_EQ(tissue.divergences(), 0);
    const Eigen::Matrix3Xd x = tissue.positions();
    EXPECT_GE((s.coarse.mesh.vertices.row(2) - x.row(2)).maxCoeff(), 0.5 * kDepth);
  }
}

// The CGAL liver (generated by the build) under a 3 mm press at its highest node: it settles below 1e-4 m/s
// within 1.5 s of simulated time. Without the mass-proportional damping it still moved at 2e-4 m/s after 7 s.
TEST(BulletTissue, APressOnTheCgalLiverSettles) {
  const scene_file::SceneDescription scene = scene_file::readSceneFile(scene_file::findSceneFile("liver"));
  const scenes::Scene coarse = scenes::buildSceneModels(scene).coarse;
  const BulletTissueOptions o = tissueOptions(scene, coarse.mesh);
  BulletTissue tissue(coarse.mesh, coarse.fixedVertices, o);
  Eigen::Index highest = 0;
  coarse.mesh.vertices.row(2).maxCoeff(&highest);
  const Eigen::Vector3d centre = coarse.mesh.vertices.col(highest) + (o.toolRadius - kDepth) * Eigen::Vector3d::UnitZ();
  tissue.setToolCentre(centre);
  EXPECT_LE(settle(tissue, centre, kSettledSpeed, static_cast<int>(1.5 / o.timeStep)), static_cast<int>(1.5 / o.timeStep));
  EXPECT_EQ(tissue.divergences(), 0);
}

TEST(BulletTissue, ResetRestoresTheRestStateExactly) {
  const Slab& s = slab();
  BulletTissue tissue(s.coarse.mesh, s.coarse.fixedVertices, s.options());
  const Eigen::Vector3d centre = s.indentingCentre(kDepth);
  tissue.setToolCentre(centre);
  settle(tissue, centre, kSettledSpeed, kMaxSettleSteps);
  ASSERT_GT(largestDeviation(tissue.positions(), s.coarse.mesh.vertices), 1e-3);

  tissue.reset();
  EXPECT_EQ(tissue.positions(), s.coarse.mesh.vertices);
  EXPECT_EQ(tissue.largestSpeed(), 0.0);
  // Parked: clear of the body, which stays at rest.
  const double clearance = (s.coarse.mesh.vertices.colwise() - tissue.toolCentre()).colwise().norm().minCoeff();
  EXPECT_GT(clearance, 2.0 * s.scene.tool.radius);
  tissue.step(50);
  EXPECT_LE(largestDeviation(tissue.positions(), s.coarse.mesh.vertices), 1e-9);
}

TEST(BulletTissue, TheTissueReturnsToRestWhenTheToolLeaves) {
  const Slab& s = slab();
  BulletTissue tissue(s.coarse.mesh, s.coarse.fixedVertices, s.options());
  const Eigen::Vector3d centre = s.indentingCentre(kDepth);
  tissue.setToolCentre(centre);
  settle(tissue, centre, kSettledSpeed, kMaxSettleSteps);

  tissue.parkTool();
  int steps = 0;
  while (++steps <= 4000 && !(tissue.step() && tissue.largestSpeed() < 1e-6)) {
  }
  EXPECT_LE(steps, 4000);
  EXPECT_LE(largestDeviation(tissue.positions(), s.coarse.mesh.vertices), 1e-4);  // elastic (1e-8 m measured)
}

TEST(BulletTissue, TheToolFollowsItsCommandAtToolSpeed) {
  const Slab& s = slab();
  BulletTissueOptions o = s.options();
  BulletTissue tissue(s.coarse.mesh, s.coarse.fixedVertices, o);
  const Eigen::Vector3d centre = s.indentingCentre(kDepth);
  tissue.setToolCentre(centre);  // parked: it enters two radii above the surface point nearest the command
  const Eigen::Vector3d first = tissue.toolCentre();
  EXPECT_NEAR(first.z(), s.contact().z() + 2.0 * o.toolRadius, 1e-12);
  tissue.step();  // then toolSpeed x timeStep a step
  EXPECT_NEAR((tissue.toolCentre() - first).norm(), o.toolSpeed * o.timeStep, 1e-12);
}

// The slab's thinnest tets lie in its 1 mm skin layer (0.995 mm high over their largest face), and a pressure
// wave crosses them at sqrt((lambda + 2 mu) / rho) = 6.16 m/s.
TEST(BulletTissue, TheStableStepIsOneAndAHalfPressureWaveCrossingsOfTheThinnestTet) {
  const Slab& s = slab();
  const double wave = 6.16;
  const double step = bullet_engine::stableTimeStep(s.coarse.mesh, s.scene.material.young, s.scene.material.poisson, 1000.0);
  EXPECT_GT(step, 1.5 * 0.0009 / wave);
  EXPECT_LT(step, 1.5 * 0.0010 / wave);
  // Four times as dense: waves half as fast, steps twice as long.
  EXPECT_NEAR(bullet_engine::stableTimeStep(s.coarse.mesh, s.scene.material.young, s.scene.material.poisson, 4000.0), 2.0 * step, 1e-15);
  expectErrorContaining<InvalidInputError>([&] { bullet_engine::stableTimeStep(s.coarse.mesh, 1e4, 0.5, 1000.0); }, "poisson");
  expectErrorContaining<InvalidInputError>([&] { bullet_engine::stableTimeStep(mesh::TetMesh{}, 1e4, 0.45, 1000.0); }, "no vertices");
}

TEST(BulletTissue, BadInputIsRefusedWithItsName) {
  const Slab& s = slab();
  const auto make = [&](const BulletTissueOptions& o) { BulletTissue tissue(s.coarse.mesh, s.coarse.fixedVertices, o); };
  const std::vector<std::pair<double BulletTissueOptions::*, const char*>> positive{
      {&BulletTissueOptions::young, "young"},       {&BulletTissueOptions::density, "density"},
      {&BulletTissueOptions::damping, "damping"},   {&BulletTissueOptions::timeStep, "timeStep"},
      {&BulletTissueOptions::toolRadius, "toolRadius"}, {&BulletTissueOptions::toolSpeed, "toolSpeed"}};
  for (const auto& [member, name] : positive)
    for (double bad : {0.0, -1.0, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
      BulletTissueOptions o = s.options();
      o.*member = bad;
      expectErrorContaining<InvalidInputError>([&] { make(o); }, name);
    }
  for (double bad : {-1.0, 1.0 / s.options().timeStep, std::numeric_limits<double>::quiet_NaN()}) {
    BulletTissueOptions o = s.options();
    o.massDamping = bad;
    expectErrorContaining<InvalidInputError>([&] { make(o); }, "massDamping");
  }
  for (double bad : {0.0, 0.5, -0.2, std::numeric_limits<double>::quiet_NaN()}) {
    BulletTissueOptions o = s.options();
    o.poisson = bad;
    expectErrorContaining<InvalidInputError>([&] { make(o); }, "poisson");
  }
  expectErrorContaining<InvalidInputError>([&] { BulletTissue tissue(mesh::TetMesh{}, {}, s.options()); }, "no vertices");
  const int beyond = static_cast<int>(s.coarse.mesh.numVertices());
  expectErrorContaining<InvalidInputError>([&] { BulletTissue tissue(s.coarse.mesh, {beyond}, s.options()); }, "fixed vertex");

  BulletTissue tissue(s.coarse.mesh, s.coarse.fixedVertices, s.options());
  expectErrorContaining<InvalidInputError>([&] { tissue.setToolCentre(Eigen::Vector3d(0.0, std::nan(""), 0.0)); }, "not finite");
}
