// Direct minimisation of eq. 4: its gradient against finite differences, stationarity, comparison with
// the flow and the initial path, reduced vs full, and the ghost-mesh approximation.
#include <gtest/gtest.h>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/shape_space/affine_subspace.hpp"
#include "deformation_enrichment/shape_space/discrete_shells.hpp"
#include "deformation_enrichment/shape_space/evaluation_space.hpp"
#include "deformation_enrichment/shape_space/geodesic.hpp"
#include "deformation_enrichment/shape_space/geodesic_path.hpp"
#include "deformation_enrichment/shape_space/rigid_interpolation.hpp"
#include "flow_test_sequences.hpp"

namespace ss = deformation_enrichment::shape_space;
namespace de = deformation_enrichment;
using namespace ss::test;

namespace {

struct PathSetup {
  FlatMesh base = bumpyGrid(5, 31);
  ss::DiscreteShells energy{base.triangles, base.vertices.size() / 3, ss::DiscreteShellsOptions::classic()};
  int serial = (energy.setThreadCount(1), 1);  // 25 vertices: threads would only spin
  Eigen::VectorXd a = bent(base.vertices, 0.2);
  Eigen::VectorXd b = bent(base.vertices, 2.5, 0.15);

  std::vector<Eigen::VectorXd> interpolation(int count) const {
    std::vector<Eigen::VectorXd> path;
    for (int k = 0; k < count; ++k) path.push_back(ss::rigidAwareInterpolation(a, b, k / double(count - 1)));
    return path;
  }
  /// Energies evaluated on the mesh itself (no ghost mesh).
  ss::EvaluationSpace exactSpace(const std::vector<Eigen::VectorXd>& path) const {
    return ss::EvaluationSpace(energy, base.triangles, path.front(), ss::ReductionOptions{});
  }
};

double innerSquaredNorm(const std::vector<Eigen::VectorXd>& g) {
  double sum = 0.0;
  for (size_t k = 1; k + 1 < g.size(); ++k) sum += g[k].squaredNorm();
  return sum;
}

}  // namespace

TEST(GeodesicPath, PathEnergyGradientMatchesFiniteDifferences) {
  PathSetup s;
  std::vector<Eigen::VectorXd> path = s.interpolation(4);
  for (size_t k = 1; k < 3; ++k) path[k] = perturbed(path[k], 0.01, unsigned(k));
  std::vector<Eigen::VectorXd> gradients;
  const double e0 = ss::pathEnergy(s.energy, path, false, &gradients);
  EXPECT_NEAR(e0, ss::pathEnergy(s.energy, path), 1e-14 * e0);
  const double h = 1e-6;
  for (size_t k = 0; k < path.size(); ++k) {
    for (Eigen::Index i : {Eigen::Index(0), Eigen::Index(17), path[k].size() - 1}) {
      std::vector<Eigen::VectorXd> plus = path, minus = path;
      plus[k][i] += h;
      minus[k][i] -= h;
      const double fd = (ss::pathEnergy(s.energy, plus) - ss::pathEnergy(s.energy, minus)) / (2 * h);
      EXPECT_NEAR(gradients[k][i], fd, 1e-6 * std::max(1.0, std::abs(fd))) << "shape " << k << " coordinate " << i;
    }
  }
}

// flowTangents and the reduced Hessian model rely on d1d1 W(x, x) = d2d2 W(x, x) = -d1d2 W(x, x).
TEST(GeodesicPath, HessianBlocksAgreeAtTheIdentity) {
  const FlatMesh mesh = bumpyGrid(6, 8);
  for (const auto& parameters : {ss::DiscreteShellsOptions::classic(), ss::DiscreteShellsOptions::hyperelastic()}) {
    const ss::DiscreteShells energy(mesh.triangles, mesh.vertices.size() / 3, parameters);
    const Eigen::VectorXd x = perturbed(mesh.vertices, 0.02, 3);
    const Eigen::MatrixXd hd = Eigen::MatrixXd(energy.hessianDeformed(x, x));
    const Eigen::MatrixXd hr = Eigen::MatrixXd(energy.hessianReference(x, x));
    const Eigen::MatrixXd hm = Eigen::MatrixXd(energy.hessianMixed(x, x));
    EXPECT_LT((hr - hd).norm(), 1e-9 * hd.norm());
    EXPECT_LT((hm + hd).norm(), 1e-9 * hd.norm());
  }
}

TEST(GeodesicPath, FullNewtonReachesAStationaryPathBelowTheInitialAndTheFlows) {
  PathSetup s;
  std::vector<Eigen::VectorXd> path = s.interpolation(5);
  const double initial = ss::pathEnergy(s.energy, path);
  const ss::PathSolveReport report = ss::minimisePathEnergyFull(s.energy, path);
  EXPECT_TRUE(report.converged);
  EXPECT_LE(report.gradientSquaredNorm, report.threshold);
  std::vector<Eigen::VectorXd> gradients;
  const double minimised = ss::pathEnergy(s.energy, path, false, &gradients);
  EXPECT_LT(minimised, 0.99 * initial);
  // Stationary: eq. 3 holds at every inner shape (the rule's bound: 1e-8 per degree of freedom).
  EXPECT_LE(innerSquaredNorm(gradients), 1e-8 * double(3 * path[0].size()));
  // The paper's flow (eq. 1 averages, same ends and shape count) cannot end lower: it seeks the same
  // critical point by many small steps.
  ss::GeodesicOptions flow;
  flow.shapes = 5;
  flow.solver = ss::GeodesicSolver::Flow;
  flow.insertPerSegment = 3;  // straight to 5 shapes, like the direct solve
  flow.tau = 1.0;
  flow.average.symmetric = true;
  const ss::GeodesicResult g = ss::geodesic(s.energy, s.base.triangles, s.a, s.b, flow);
  EXPECT_LE(minimised, g.pathEnergy * (1.0 + 1e-9));
  EXPECT_NEAR(minimised, g.pathEnergy, 1e-3 * minimised);  // and both find the same geodesic
}

TEST(GeodesicPath, ReducedSolveMeetsTheReducedStoppingRule) {
  PathSetup s;
  std::vector<Eigen::VectorXd> path = s.interpolation(5);
  const double initial = ss::pathEnergy(s.energy, path);
  ss::AffineSubspace subspace = ss::pcaSubspace(path, 8);
  ss::enrich(subspace, ss::flowTangents(s.energy, path, false));
  const ss::PathSolveReport report = ss::minimisePathEnergyReduced(s.exactSpace(path), path, subspace.basis);
  EXPECT_TRUE(report.converged);
  EXPECT_GT(report.iterations, 0);
  // Recompute the reduced gradient independently: sum_k |B^T d(eq. 4)/dx_k|^2.
  std::vector<Eigen::VectorXd> gradients;
  const double minimised = ss::pathEnergy(s.energy, path, false, &gradients);
  double reduced = 0.0;
  for (size_t k = 1; k + 1 < path.size(); ++k) reduced += (subspace.basis.transpose() * gradients[k]).squaredNorm();
  EXPECT_LE(reduced, report.threshold * 1.0001);
  EXPECT_NEAR(reduced, report.gradientSquaredNorm, 1e-6 * report.threshold);
  EXPECT_LT(minimised, 0.99 * initial);
}

TEST(GeodesicPath, ReducedAndFullLengthsAgreeWithinPointOnePercent) {
  PathSetup s;
  ss::GeodesicOptions full;
  full.shapes = 8;
  ss::GeodesicOptions reduced = full;
  reduced.reduction.reduced = true;
  reduced.reduction.subspaceDimension = 8;
  const ss::GeodesicResult gf = ss::geodesic(s.energy, s.base.triangles, s.a, s.b, full);
  const ss::GeodesicResult gr = ss::geodesic(s.energy, s.base.triangles, s.a, s.b, reduced);
  EXPECT_TRUE(gf.converged);
  EXPECT_TRUE(gr.converged);
  EXPECT_LT(std::abs(gr.length - gf.length), 1e-3 * gf.length) << "full " << gf.length << " reduced " << gr.length;
  EXPECT_GE(gr.pathEnergy, gf.pathEnergy * (1.0 - 1e-9));  // the full minimiser is the lower bound
  EXPECT_EQ(gr.ghostVertices, 0);
}

TEST(GeodesicPath, GhostMeshApproximatesTheReducedGeodesic) {
  const FlatMesh base = bumpyGrid(25, 9);  // 625 vertices; the ghost has 200
  ss::DiscreteShells energy(base.triangles, base.vertices.size() / 3);
  energy.setThreadCount(1);
  const Eigen::VectorXd a = bent(base.vertices, 0.3), b = bent(base.vertices, 2.0, 0.1);
  ss::GeodesicOptions exact;
  exact.shapes = 5;
  exact.reduction.reduced = true;
  exact.reduction.subspaceDimension = 8;
  exact.reduction.useGhostMesh = false;
  ss::GeodesicOptions ghost = exact;
  ghost.reduction.useGhostMesh = true;
  ghost.reduction.ghostMesh.targetVertices = 200;
  const ss::GeodesicResult ge = ss::geodesic(energy, base.triangles, a, b, exact);
  const ss::GeodesicResult gg = ss::geodesic(energy, base.triangles, a, b, ghost);
  EXPECT_EQ(ge.ghostVertices, 0);
  EXPECT_GT(gg.ghostVertices, 150);
  EXPECT_LE(gg.ghostVertices, 200);
  EXPECT_TRUE(gg.converged);
  // Lengths are reported on the fine mesh; the ghost's path is close to, and not below, the exact one.
  EXPECT_LT(std::abs(gg.length - ge.length), 0.02 * ge.length) << "exact " << ge.length << " ghost " << gg.length;
  EXPECT_GE(gg.pathEnergy, ge.pathEnergy * (1.0 - 1e-3));
  std::vector<Eigen::VectorXd> linear;
  for (int k = 0; k < 5; ++k) linear.push_back(ss::rigidAwareInterpolation(a, b, k / 4.0));
  EXPECT_LT(gg.pathEnergy, ss::pathEnergy(energy, linear));
}

TEST(GeodesicPath, BadInputGivesClearErrors) {
  PathSetup s;
  std::vector<Eigen::VectorXd> two{s.a, s.b};
  EXPECT_THROW(ss::minimisePathEnergyFull(s.energy, two), de::InvalidInputError);
  std::vector<Eigen::VectorXd> path = s.interpolation(4);
  EXPECT_THROW(ss::minimisePathEnergyReduced(s.exactSpace(path), path, Eigen::MatrixXd(path[0].size(), 0)),
               de::InvalidInputError);
  EXPECT_THROW(ss::minimisePathEnergyReduced(s.exactSpace(path), path, Eigen::MatrixXd::Ones(7, 2)),
               de::InvalidInputError);
  path[2][5] = std::nan("");
  EXPECT_THROW(ss::minimisePathEnergyFull(s.energy, path), de::InvalidInputError);
  ss::GeodesicOptions opt;
  opt.enrichmentRounds = -1;
  EXPECT_THROW(ss::geodesic(s.energy, s.base.triangles, s.a, s.b, opt), de::InvalidInputError);
}
