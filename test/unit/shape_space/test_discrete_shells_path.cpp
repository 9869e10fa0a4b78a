// DiscreteShells::pathSegments (eq. 4's terms from per-shape element data) against the interface's default
// (both directions of every segment evaluated term by term), against finite differences, serial against
// parallel, on hinges folding through +-pi, and its errors; eq. 4 from kept reference data.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/shape_space/discrete_shells.hpp"
#include "shell_test_meshes.hpp"

namespace deformation_enrichment::shape_space {
namespace {

using Eigen::VectorXd;

std::vector<VectorXd> noisyPath(const test::FlatMesh& mesh, int count, double amplitude) {
  std::vector<VectorXd> path;
  for (int k = 0; k < count; ++k) path.push_back(test::perturbed(mesh.vertices, amplitude, unsigned(11 + k)));
  return path;
}

// Segment values and per-shape gradients of `energy` equal those of the default implementation.
void expectSameAsDefault(const DiscreteShells& energy, const std::vector<VectorXd>& path, bool closed) {
  const test::ForwardingEnergy reference(energy);
  std::vector<VectorXd> gradients, expectedGradients;
  const std::vector<double> values = energy.pathSegments(path, closed, &gradients, true);
  const std::vector<double> expected = reference.pathSegments(path, closed, &expectedGradients, true);
  ASSERT_EQ(values.size(), expected.size());
  EXPECT_EQ(values.size(), closed ? path.size() : path.size() - 1);
  // Relative, plus the round-off of the membrane's cancelling O(area) terms (these meshes have area ~1).
  for (size_t s = 0; s < values.size(); ++s) EXPECT_NEAR(values[s], expected[s], 1e-12 * expected[s] + 1e-14) << "segment " << s;
  ASSERT_EQ(gradients.size(), path.size());
  for (size_t k = 0; k < path.size(); ++k)
    EXPECT_LT((gradients[k] - expectedGradients[k]).norm(), 1e-11 * expectedGradients[k].norm()) << "shape " << k;
  const std::vector<double> valuesOnly = energy.pathSegments(path, closed, nullptr, true);
  for (size_t s = 0; s < values.size(); ++s) EXPECT_NEAR(valuesOnly[s], values[s], 1e-13 * values[s] + 1e-15);
}

// One hinge (0, 1, 2) | (1, 0, 3) about the x axis, the second triangle turned by alpha from flat.
VectorXd hinge(double alpha) {
  VectorXd x(12);
  x << 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.5, 1.0, 0.0, 0.5, -std::cos(alpha), std::sin(alpha);
  return x;
}

}  // namespace

TEST(PathSegments, EqualTheTermByTermSumForBothMembranesOpenAndClosed) {
  const test::FlatMesh mesh = test::bumpyGrid(6, 21);
  for (const auto& parameters : {DiscreteShellsOptions::classic(), DiscreteShellsOptions::hyperelastic(0.3)}) {
    const DiscreteShells energy(mesh.triangles, mesh.vertices.size() / 3, parameters);
    const std::vector<VectorXd> path = noisyPath(mesh, 5, 0.05);
    expectSameAsDefault(energy, path, false);
    expectSameAsDefault(energy, path, true);
    expectSameAsDefault(energy, {path[0], path[1]}, true);  // two shapes, closed: both segments join them
  }
}

TEST(PathSegments, WithoutEndGradientsTheInnerOnesAreUnchanged) {
  const test::FlatMesh mesh = test::bumpyGrid(33, 8);  // 1089 vertices: the parallel runs split the path
  DiscreteShells energy(mesh.triangles, mesh.vertices.size() / 3, DiscreteShellsOptions::hyperelastic());
  const test::ForwardingEnergy reference(energy);
  const std::vector<VectorXd> path = noisyPath(mesh, 5, 0.002);
  for (const int threads : {1, 3}) {
    energy.setThreadCount(threads);
    for (const DeformationEnergy* e : {static_cast<const DeformationEnergy*>(&energy), static_cast<const DeformationEnergy*>(&reference)}) {
      std::vector<VectorXd> all, inner;
      const std::vector<double> values = e->pathSegments(path, false, &all, true);
      const std::vector<double> innerValues = e->pathSegments(path, false, &inner, false);
      for (size_t s = 0; s < values.size(); ++s) EXPECT_NEAR(innerValues[s], values[s], 1e-14 * values[s]);
      ASSERT_EQ(inner.size(), path.size());
      EXPECT_EQ(inner.front().norm(), 0.0);
      EXPECT_EQ(inner.back().norm(), 0.0);
      EXPECT_GT(all.front().norm(), 0.0);
      for (size_t k = 1; k + 1 < path.size(); ++k) EXPECT_LT((inner[k] - all[k]).norm(), 1e-14 * all[k].norm()) << "shape " << k;
    }
  }
}

TEST(PathSegments, WrapTheAngleDifferenceOfAHingeFoldingThroughPi) {
  Eigen::Matrix3Xi triangles(3, 2);
  triangles << 0, 1, 1, 0, 2, 3;
  for (const auto& parameters : {DiscreteShellsOptions::classic(), DiscreteShellsOptions::hyperelastic()}) {
    const DiscreteShells energy(triangles, 4, parameters);
    ASSERT_EQ(energy.numHinges(), 1);
    // theta = +-(pi - 0.1): the hinges differ by 0.2 rad through the fold, not by 2 pi - 0.2.
    const std::vector<VectorXd> path{hinge(M_PI - 0.1), hinge(-(M_PI - 0.1)), hinge(M_PI - 0.15)};
    expectSameAsDefault(energy, path, false);
    const double bending = energy.bendingValue(path[0], path[1]) + energy.bendingValue(path[1], path[0]);
    EXPECT_LT(bending, 0.2 * 0.2 * 10.0 * parameters.bendingWeight);
  }
}

TEST(PathSegments, GradientsMatchFiniteDifferences) {
  const test::FlatMesh mesh = test::bumpyGrid(5, 4);
  for (const auto& parameters : {DiscreteShellsOptions::classic(), DiscreteShellsOptions::hyperelastic(0.3)}) {
    const DiscreteShells energy(mesh.triangles, mesh.vertices.size() / 3, parameters);
    const std::vector<VectorXd> path = noisyPath(mesh, 3, 0.04);
    std::vector<VectorXd> gradients;
    energy.pathSegments(path, true, &gradients, true);
    const auto total = [&](const std::vector<VectorXd>& shapes) {
      double sum = 0.0;
      for (double s : energy.pathSegments(shapes, true, nullptr, true)) sum += s;
      return sum;
    };
    const double h = 1e-6;
    for (size_t k = 0; k < path.size(); ++k) {
      for (const Eigen::Index i : {Eigen::Index(0), Eigen::Index(31), path[k].size() - 1}) {
        std::vector<VectorXd> plus = path, minus = path;
        plus[k][i] += h;
        minus[k][i] -= h;
        const double fd = (total(plus) - total(minus)) / (2.0 * h);
        EXPECT_NEAR(gradients[k][i], fd, 1e-6 * std::max(1.0, std::abs(fd))) << "shape " << k << " coordinate " << i;
      }
    }
  }
}

TEST(PathSegments, SerialAndParallelAgree) {
  const test::FlatMesh mesh = test::bumpyGrid(33, 5);  // 1089 vertices: above the parallel threshold
  DiscreteShells energy(mesh.triangles, mesh.vertices.size() / 3, DiscreteShellsOptions::hyperelastic());
  const std::vector<VectorXd> path = noisyPath(mesh, 7, 0.002);
  std::vector<VectorXd> serialGradients, parallelGradients;
  energy.setThreadCount(1);
  const std::vector<double> serial = energy.pathSegments(path, true, &serialGradients, true);
  energy.setThreadCount(3);
  const std::vector<double> parallel = energy.pathSegments(path, true, &parallelGradients, true);
  for (size_t s = 0; s < serial.size(); ++s) EXPECT_NEAR(serial[s], parallel[s], 1e-13 * serial[s]);
  for (size_t k = 0; k < path.size(); ++k)
    EXPECT_LT((serialGradients[k] - parallelGradients[k]).norm(), 1e-12 * serialGradients[k].norm());
}

// Eq. 4 from the shapes' reference data (no pass over the shapes) is pathSegments' sum, for both membranes,
// with and without bending, open and closed; data of another energy is refused, the interface's default
// offers none.
TEST(PathSegments, PathEnergyFromReferenceDataIsTheirSum) {
  const test::FlatMesh mesh = test::bumpyGrid(6, 21);
  DiscreteShellsOptions flat = DiscreteShellsOptions::hyperelastic(0.3);
  flat.bendingWeight = 0.0;
  for (const auto& parameters : {DiscreteShellsOptions::classic(), DiscreteShellsOptions::hyperelastic(0.3), flat}) {
    const DiscreteShells energy(mesh.triangles, mesh.vertices.size() / 3, parameters);
    const std::vector<VectorXd> path = noisyPath(mesh, 5, 0.05);
    std::vector<std::shared_ptr<const ReferenceData>> kept;
    std::vector<const ReferenceData*> data;
    for (const VectorXd& x : path) data.push_back(kept.emplace_back(energy.referenceData(x)).get());
    for (bool closed : {false, true}) {
      double sum = 0.0;
      for (double segment : energy.pathSegments(path, closed, nullptr, false)) sum += segment;
      const std::optional<double> fromData = energy.pathEnergy(data, closed);
      ASSERT_TRUE(fromData.has_value());
      EXPECT_NEAR(*fromData, sum, 1e-13 * sum) << "closed " << closed;
    }
    EXPECT_THROW(energy.pathEnergy({data[0]}, false), InvalidInputError);
    const DiscreteShells other(mesh.triangles, mesh.vertices.size() / 3,
                               parameters.membrane == MembraneModel::Hyperelastic ? DiscreteShellsOptions::classic()
                                                                                  : DiscreteShellsOptions::hyperelastic(0.3));
    const auto foreign = other.referenceData(path[2]);
    EXPECT_THROW(energy.pathEnergy({data[0], data[1], foreign.get()}, false), InvalidInputError);
    EXPECT_THROW(energy.pathEnergy({data[0], nullptr}, false), InvalidInputError);
    EXPECT_FALSE(test::ForwardingEnergy(energy).pathEnergy(data, false).has_value());
  }
}

TEST(PathSegments, BadInputGivesClearErrors) {
  const test::FlatMesh mesh = test::bumpyGrid(4, 2);
  const DiscreteShells energy(mesh.triangles, mesh.vertices.size() / 3, DiscreteShellsOptions::hyperelastic());
  std::vector<VectorXd> path = noisyPath(mesh, 3, 0.01);
  EXPECT_THROW(energy.pathSegments({path[0]}, false, nullptr, true), InvalidInputError);
  path[1].segment<3>(3) = path[1].segment<3>(0);  // collapses the triangles at vertices 0 and 1
  try {
    energy.pathSegments(path, false, nullptr, true);
    ADD_FAILURE() << "a degenerate shape was accepted";
  } catch (const InvalidInputError& e) {
    EXPECT_NE(std::string(e.what()).find("shape 1 of the path is degenerate"), std::string::npos) << e.what();
  }
  path[1] = path[0];
  path[2][4] = std::nan("");
  EXPECT_THROW(energy.pathSegments(path, false, nullptr, true), InvalidInputError);
  path[2].resize(6);
  EXPECT_THROW(energy.pathSegments(path, false, nullptr, true), InvalidInputError);
}

}  // namespace deformation_enrichment::shape_space
