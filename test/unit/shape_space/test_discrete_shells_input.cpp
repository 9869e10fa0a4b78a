// Documented behaviour of the Discrete Shells energies on awkward input: non-manifold edges and boundary
// edges skip bending, winding does not matter, degenerate triangles and malformed shapes or topologies
// raise InvalidInputError naming the problem, and nearly degenerate (but valid) triangles stay finite.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/shape_space/discrete_shells.hpp"
#include "shell_test_meshes.hpp"

namespace deformation_enrichment::shape_space {
namespace {

using Eigen::VectorXd;


bool allFinite(const test::AllOutputs& r) {
  auto finiteSparse = [](const Eigen::SparseMatrix<double>& m) {
    for (Eigen::Index k = 0; k < m.nonZeros(); ++k) {
      if (!std::isfinite(m.valuePtr()[k])) return false;
    }
    return true;
  };
  return std::isfinite(r.value) && r.gradientDeformed.allFinite() && r.gradientReference.allFinite() &&
         finiteSparse(r.hessianDeformed) && finiteSparse(r.hessianMixed) && finiteSparse(r.hessianReference);
}

// Expects InvalidInputError whose message contains every one of the given fragments.
template <class F>
void expectInvalidInput(F&& f, std::initializer_list<const char*> fragments) {
  try {
    f();
    ADD_FAILURE() << "no InvalidInputError thrown";
  } catch (const InvalidInputError& e) {
    for (const char* fragment : fragments) {
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << "message '" << e.what() << "' lacks '" << fragment << "'";
    }
  }
}

TEST(DiscreteShellsInput, EdgeWithThreeTrianglesIsSkippedForBending) {
  // Hinge (0,1,2)/(1,0,3) plus a fin (0,1,4) on the same edge: the edge is non-manifold.
  VectorXd x(15);
  x << 0, 0, 0, 1, 0, 0, 0.5, 1, 0, 0.5, -1, 0, 0.5, 0, 1;
  Eigen::Matrix3Xi withFin(3, 3), hingeOnly(3, 2);
  withFin << 0, 1, 0, 1, 0, 1, 2, 3, 4;
  hingeOnly << 0, 1, 1, 0, 2, 3;
  const DiscreteShells finEnergy(withFin, 5, DiscreteShellsOptions::classic());
  const DiscreteShells hingeEnergy(hingeOnly, 5, DiscreteShellsOptions::classic());
  EXPECT_EQ(finEnergy.numNonManifoldEdges(), 1);
  EXPECT_EQ(finEnergy.numHinges(), 0);
  EXPECT_EQ(finEnergy.numBoundaryEdges(), 6);
  EXPECT_EQ(finEnergy.numEdges(), 7);
  EXPECT_EQ(hingeEnergy.numHinges(), 1);
  VectorXd folded = x;
  folded.segment<3>(6) << 0.5, 0.7, 0.7;  // fold the hinge
  EXPECT_GT(hingeEnergy.bendingValue(x, folded), 0.1);
  EXPECT_EQ(finEnergy.bendingValue(x, folded), 0.0);
  const test::AllOutputs r = test::evaluateAll(finEnergy, x, folded);
  EXPECT_TRUE(allFinite(r));
  EXPECT_GT(r.value, 0.0);  // the membrane still sees the stretched triangle
}

TEST(DiscreteShellsInput, HingeFoldingThroughPiDoesNotJump) {
  // Wing l turns about the edge (0,0,0)-(1,0,0); phi = 0 is flat, phi = pi folds it onto wing k.
  auto hinge = [](double phi) {
    VectorXd x(12);
    x << 0, 0, 0, 1, 0, 0, 0.5, 1, 0, 0.5, -std::cos(phi), std::sin(phi);
    return x;
  };
  Eigen::Matrix3Xi triangles(3, 2);
  triangles << 0, 1, 1, 0, 2, 3;
  const DiscreteShells energy(triangles, 4, DiscreteShellsOptions::classic());
  ASSERT_EQ(energy.numHinges(), 1);
  const double acrossPi = energy.bendingValue(hinge(M_PI - 0.05), hinge(M_PI + 0.05));
  const double belowPi = energy.bendingValue(hinge(M_PI - 0.15), hinge(M_PI - 0.05));
  EXPECT_GT(belowPi, 0.0);
  EXPECT_NEAR(acrossPi, belowPi, 1e-9 * belowPi);
  // Same 0.1 rad change as in a flat region: the weight 3 |e|^2 / (A1 + A2) = 3 here.
  EXPECT_NEAR(belowPi, 3.0 * 0.01, 1e-9);
  EXPECT_NEAR(energy.bendingValue(hinge(0.0), hinge(0.1)), belowPi, 1e-9 * belowPi);
}

TEST(DiscreteShellsInput, DuplicatedTriangleCountsAsNonManifold) {
  VectorXd x(9);
  x << 0, 0, 0, 1, 0, 0, 0, 1, 0;
  Eigen::Matrix3Xi twice(3, 2);
  twice << 0, 0, 1, 2, 2, 1;  // the same triangle with opposite winding
  const DiscreteShells energy(twice, 3, DiscreteShellsOptions::hyperelastic());
  EXPECT_EQ(energy.numHinges(), 0);
  EXPECT_EQ(energy.numNonManifoldEdges(), 3);
  EXPECT_TRUE(std::isfinite(energy.value(x, 1.1 * x)));
}

TEST(DiscreteShellsInput, FinOnAGridRemovesOnlyItsOwnHinge) {
  const test::FlatMesh grid = test::bumpyGrid(5, 6);
  const DiscreteShells plain(grid.triangles, 25, DiscreteShellsOptions::hyperelastic());
  Eigen::Matrix3Xi withFin(3, grid.triangles.cols() + 1);
  withFin << grid.triangles, Eigen::Vector3i(grid.triangles(0, 10), grid.triangles(1, 10), 25);
  VectorXd vertices(3 * 26);
  vertices << grid.vertices, 0.5, 0.5, 1.0;
  const DiscreteShells finned(withFin, 26, DiscreteShellsOptions::hyperelastic());
  EXPECT_EQ(finned.numHinges(), plain.numHinges() - 1);
  EXPECT_EQ(finned.numNonManifoldEdges(), 1);
  EXPECT_EQ(plain.numBoundaryEdges(), 16);
  EXPECT_TRUE(allFinite(test::evaluateAll(finned, vertices, test::perturbed(vertices, 0.05, 2))));
}

TEST(DiscreteShellsInput, TriangleWindingDoesNotChangeTheEnergy) {
  const test::FlatMesh mesh = test::bumpyGrid(6, 7);
  Eigen::Matrix3Xi flipped = mesh.triangles;
  for (Eigen::Index t = 0; t < flipped.cols(); t += 3) std::swap(flipped(1, t), flipped(2, t));
  for (const auto& parameters : {DiscreteShellsOptions::hyperelastic(0.3), DiscreteShellsOptions::classic()}) {
    const DiscreteShells consistent(mesh.triangles, 36, parameters);
    const DiscreteShells mixed(flipped, 36, parameters);
    const VectorXd deformed = test::perturbed(mesh.vertices, 0.06, 3);
    const test::AllOutputs a = test::evaluateAll(consistent, mesh.vertices, deformed);
    const test::AllOutputs b = test::evaluateAll(mixed, mesh.vertices, deformed);
    EXPECT_NEAR(a.value, b.value, 1e-12 * a.value);
    EXPECT_LT((a.gradientDeformed - b.gradientDeformed).norm(), 1e-11 * a.gradientDeformed.norm());
    EXPECT_LT((a.hessianReference - b.hessianReference).norm(), 1e-11 * a.hessianReference.norm());
  }
}

TEST(DiscreteShellsInput, DegenerateTrianglesAreNamed) {
  const test::FlatMesh mesh = test::bumpyGrid(4, 8);
  const DiscreteShells energy(mesh.triangles, 16, DiscreteShellsOptions::hyperelastic());
  const int t = 7;
  const int a = mesh.triangles(0, t), b = mesh.triangles(1, t), c = mesh.triangles(2, t);
  VectorXd collinear = mesh.vertices;  // c moved onto the segment ab
  collinear.segment<3>(3 * c) = 0.5 * (collinear.segment<3>(3 * a) + collinear.segment<3>(3 * b));
  expectInvalidInput([&] { energy.value(collinear, mesh.vertices); }, {"triangle", "reference", "degenerate"});
  expectInvalidInput([&] { energy.gradientDeformed(mesh.vertices, collinear); }, {"deformed", "degenerate"});
  VectorXd collapsed = mesh.vertices;  // two corners on top of each other
  collapsed.segment<3>(3 * b) = collapsed.segment<3>(3 * a);
  expectInvalidInput([&] { energy.hessianDeformed(mesh.vertices, collapsed); }, {"deformed", "degenerate"});
}

TEST(DiscreteShellsInput, NearlyDegenerateTrianglesStayFinite) {
  // A sliver of relative area 1e-6 (above the 1e-8 threshold) in both shapes.
  VectorXd x(12);
  x << 0, 0, 0, 1, 0, 0, 0.5, 1e-6, 0, 0.5, -1, 0;
  Eigen::Matrix3Xi triangles(3, 2);
  triangles << 0, 1, 1, 0, 2, 3;
  for (const auto& parameters : {DiscreteShellsOptions::hyperelastic(0.5), DiscreteShellsOptions::classic()}) {
    const DiscreteShells energy(triangles, 4, parameters);
    VectorXd deformed = x;
    deformed.segment<3>(6) << 0.5, 2e-6, 1e-6;
    const test::AllOutputs r = test::evaluateAll(energy, x, deformed);
    EXPECT_TRUE(allFinite(r)) << "value " << r.value;
  }
}

TEST(DiscreteShellsInput, MalformedShapesAndTopologiesAreRejected) {
  const test::FlatMesh mesh = test::bumpyGrid(3, 9);
  const DiscreteShells energy(mesh.triangles, 9, DiscreteShellsOptions::hyperelastic());
  VectorXd withNan = mesh.vertices;
  withNan[13] = std::numeric_limits<double>::quiet_NaN();
  expectInvalidInput([&] { energy.value(mesh.vertices, withNan); }, {"deformed", "non-finite", "vertex 4"});
  expectInvalidInput([&] { energy.value(withNan, mesh.vertices); }, {"reference", "non-finite"});
  expectInvalidInput([&] { energy.value(mesh.vertices, mesh.vertices.head(12)); }, {"deformed", "12 entries"});
  Eigen::Matrix3Xi outOfRange = mesh.triangles;
  outOfRange(2, 3) = 9;
  expectInvalidInput([&] { DiscreteShells(outOfRange, 9); }, {"triangle 3", "index 9"});
  Eigen::Matrix3Xi repeated = mesh.triangles;
  repeated(1, 2) = repeated(0, 2);
  expectInvalidInput([&] { DiscreteShells(repeated, 9); }, {"triangle 2", "repeats"});
  expectInvalidInput([&] { DiscreteShells(Eigen::Matrix3Xi(3, 0), 9); }, {"empty"});
  DiscreteShellsOptions negative = DiscreteShellsOptions::classic();
  negative.bendingWeight = -1.0;
  expectInvalidInput([&] { DiscreteShells(mesh.triangles, 9, negative); }, {"non-negative"});
}

}  // namespace
}  // namespace deformation_enrichment::shape_space
