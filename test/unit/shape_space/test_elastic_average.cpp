// Elastic average (eq. 10 and eq. 1): derivatives, stationarity, rigid motions, reduced vs full, errors.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <limits>
#include <memory>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/shape_space/discrete_shells.hpp"
#include "deformation_enrichment/shape_space/elastic_average.hpp"
#include "deformation_enrichment/shape_space/reduced_average.hpp"
#include "flow_test_sequences.hpp"

namespace ss = deformation_enrichment::shape_space;
namespace de = deformation_enrichment;
using namespace ss::test;

namespace {

struct AverageSetup {
  FlatMesh base = bumpyGrid(5, 11);
  ss::DiscreteShells energy{base.triangles, base.vertices.size() / 3, ss::DiscreteShellsOptions::classic()};
  int serial = (energy.setThreadCount(1), 1);  // tiny meshes: OpenMP overhead would dominate
  Eigen::VectorXd y0 = bent(base.vertices, 0.3);
  Eigen::VectorXd y1 = bent(base.vertices, 2.5, 0.15);
  Eigen::VectorXd y2 = perturbed(bent(base.vertices, 1.2, 0.05), 0.01, 5);
  std::vector<double> w{0.3, 0.5, 0.2};
  std::vector<const Eigen::VectorXd*> ys{&y0, &y1, &y2};
};

}  // namespace

TEST(ElasticAverage, ObjectiveGradientMatchesFiniteDifferences) {
  AverageSetup s;
  const Eigen::VectorXd y = perturbed(s.y2, 0.02, 9);
  for (bool symmetric : {false, true}) {
    Eigen::VectorXd g;
    ss::averageObjective(s.energy, s.w, s.ys, y, symmetric, &g);
    const double h = 1e-6;
    for (Eigen::Index k = 0; k < y.size(); k += 7) {
      Eigen::VectorXd p = y, m = y;
      p[k] += h;
      m[k] -= h;
      const double fd = (ss::averageObjective(s.energy, s.w, s.ys, p, symmetric, nullptr) -
                         ss::averageObjective(s.energy, s.w, s.ys, m, symmetric, nullptr)) / (2 * h);
      EXPECT_NEAR(g[k], fd, 1e-6 * (1 + std::abs(fd))) << "coordinate " << k << " symmetric " << symmetric;
    }
  }
}

TEST(ElasticAverage, MinimiserIsStationaryAndBelowEveryInput) {
  AverageSetup s;
  for (bool symmetric : {false, true}) {
    ss::AverageOptions opt;
    opt.symmetric = symmetric;
    const ss::AverageResult r = ss::elasticAverage(s.energy, s.w, s.ys, s.y2, opt);
    Eigen::VectorXd g0, g;
    const double f0 = ss::averageObjective(s.energy, s.w, s.ys, s.y2, symmetric, &g0);
    const double f = ss::averageObjective(s.energy, s.w, s.ys, r.shape, symmetric, &g);
    EXPECT_LT(g.norm(), 1e-6 * g0.norm()) << "symmetric " << symmetric;
    EXPECT_LT(f, f0);
    for (const auto* y : s.ys) EXPECT_LE(f, ss::averageObjective(s.energy, s.w, s.ys, *y, symmetric, nullptr));
  }
}

TEST(ElasticAverage, AveragingOneShapeReturnsIt) {
  AverageSetup s;
  const Eigen::VectorXd y = s.y1;
  const ss::AverageResult r = ss::elasticAverage(s.energy, {1.0, 2.0}, {&y, &y}, y);
  EXPECT_LT((r.shape - y).norm(), 1e-12);
}

TEST(ElasticAverage, ResultFollowsRigidMotions) {
  AverageSetup s;
  const ss::AverageResult r = ss::elasticAverage(s.energy, s.w, s.ys, s.y2);
  const Eigen::Matrix3d rot = someRotation(0.9);
  const Eigen::Vector3d t(1.0, -0.5, 2.0);
  // All inputs and the start moved together: the result moves the same way.
  const Eigen::VectorXd m0 = moved(s.y0, rot, t), m1 = moved(s.y1, rot, t), m2 = moved(s.y2, rot, t);
  const ss::AverageResult rm = ss::elasticAverage(s.energy, s.w, {&m0, &m1, &m2}, m2);
  EXPECT_LT((rm.shape - moved(r.shape, rot, t)).norm(), 1e-6 * r.shape.norm());
  // One example moved on its own: the energy only sees its intrinsic geometry, the result is unchanged.
  const ss::AverageResult rOne = ss::elasticAverage(s.energy, s.w, {&s.y0, &m1, &s.y2}, s.y2);
  EXPECT_LT((rOne.shape - r.shape).norm(), 1e-6 * r.shape.norm());
}

TEST(ElasticAverage, ReducedInTheFullBasisMatchesNewton) {
  AverageSetup s;
  const ss::AverageResult full = ss::elasticAverage(s.energy, s.w, s.ys, s.y2);
  auto basis = std::make_shared<const Eigen::MatrixXd>(Eigen::MatrixXd::Identity(s.y2.size(), s.y2.size()));
  const ss::ReducedSpace space = ss::makeReducedSpace(s.energy, s.y2, basis, s.y2);
  ss::ReducedAverageOptions opt;
  opt.relativeTolerance = 1e-14;  // decrement <= 1e-14 f0: near double-precision round-off of eq. 10
  opt.progressTolerance = 0.0;    // (the default rule stops at a gap of 5e-7 of the decrease: measured 2e-7 relative here)
  const ss::AverageResult reduced = ss::reducedElasticAverage(s.energy, s.w, s.ys, space, s.y2, opt);
  EXPECT_TRUE(full.converged());
  EXPECT_TRUE(reduced.converged());
  // Both are minimisers; they may differ by a rigid motion (null space), so compare energies and the
  // shapes after rigid alignment.
  EXPECT_NEAR(reduced.objective, full.objective, 1e-7 * full.objective);
  Eigen::VectorXd g;
  ss::averageObjective(s.energy, s.w, s.ys, reduced.shape, false, &g);
  Eigen::VectorXd g0;
  ss::averageObjective(s.energy, s.w, s.ys, s.y2, false, &g0);
  EXPECT_LT(g.norm(), 1e-4 * g0.norm());
}

// The warm start from the objective's own Hessian at the start (as SmoothingFlow's first step uses), made
// positive definite by its eigenvalues' magnitudes: the solver reaches the same minimum as from the rest
// Hessian of one example's energy.
TEST(ElasticAverage, WarmStartFromTheObjectivesHessian) {
  AverageSetup s;
  // A flow's average: the shape between two noisy neighbours.
  const Eigen::VectorXd before = perturbed(s.y2, 0.003, 21), after = perturbed(s.y2, 0.003, 22);
  s.ys = {&before, &s.y2, &after};
  s.w = {0.25, 0.5, 0.25};
  auto basis = std::make_shared<const Eigen::MatrixXd>(Eigen::MatrixXd::Identity(s.y2.size(), s.y2.size()));
  const ss::ReducedSpace rest = ss::makeReducedSpace(s.energy, s.y2, basis, s.y2);
  ss::ReducedSpace own = rest;
  const Eigen::MatrixXd h = ss::averageHessian(s.energy, s.w, s.ys, s.y2, false);
  ss::setWarmStart(own, h.sparseView(), 1e-5);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> hEigen(h), modelEigen(own.warmStart);
  const double ridge = 1e-5 * h.diagonal().cwiseAbs().mean();
  ASSERT_LT(hEigen.eigenvalues()[0], -ridge);  // indefinite, as away from the minimum
  Eigen::VectorXd expected = hEigen.eigenvalues().cwiseAbs().cwiseMax(ridge);
  std::sort(expected.data(), expected.data() + expected.size());
  EXPECT_LT((modelEigen.eigenvalues() - expected).norm(), 1e-10 * expected.norm());
  ss::ReducedAverageOptions options;
  options.progressTolerance = 0.0;  // both to the 1e-12 rule: the same minimum to 1e-9
  const ss::AverageResult fromRest = ss::reducedElasticAverage(s.energy, s.w, s.ys, rest, s.y2, options);
  const ss::AverageResult fromOwn = ss::reducedElasticAverage(s.energy, s.w, s.ys, own, s.y2, options);
  EXPECT_TRUE(fromRest.converged());
  EXPECT_TRUE(fromOwn.converged());
  EXPECT_NEAR(fromOwn.objective, fromRest.objective, 1e-9 * fromRest.objective);
  EXPECT_THROW(ss::setWarmStart(own, Eigen::SparseMatrix<double>(3, 3), 1e-5), de::InvalidInputError);
}

TEST(ElasticAverage, NonConvergenceReturnsTheLastIterateWithItsStatus) {
  AverageSetup s;
  const double f0 = ss::averageObjective(s.energy, s.w, s.ys, s.y2, false, nullptr);
  ss::AverageOptions opt;
  opt.maxIterations = 1;
  const ss::AverageResult full = ss::elasticAverage(s.energy, s.w, s.ys, s.y2, opt);
  EXPECT_EQ(full.status, de::numerics::MinimiserStatus::NotConverged);
  EXPECT_EQ(full.iterations, 1);
  EXPECT_LT(full.objective, f0);  // an accepted step: lower than the start
  EXPECT_NEAR(full.objective, ss::averageObjective(s.energy, s.w, s.ys, full.shape, false, nullptr), 1e-12 * f0);
  Eigen::VectorXd g;
  ss::averageObjective(s.energy, s.w, s.ys, full.shape, false, &g);
  EXPECT_NEAR(full.gradientNorm, g.norm(), 1e-9 * g.norm());
  auto basis = std::make_shared<const Eigen::MatrixXd>(Eigen::MatrixXd::Identity(s.y2.size(), s.y2.size()));
  const ss::ReducedSpace space = ss::makeReducedSpace(s.energy, s.y2, basis, s.y2);
  ss::ReducedAverageOptions ropt;
  ropt.maxIterations = 2;
  const ss::AverageResult reduced = ss::reducedElasticAverage(s.energy, s.w, s.ys, space, s.y2, ropt);
  EXPECT_EQ(reduced.status, de::numerics::MinimiserStatus::NotConverged);
  EXPECT_LT(reduced.objective, f0);
  EXPECT_GT(reduced.gradientNorm, 0.0);
}

TEST(ElasticAverage, BadInputGivesClearErrors) {
  AverageSetup s;
  EXPECT_THROW(ss::elasticAverage(s.energy, {1.0}, s.ys, s.y2), de::InvalidInputError);
  EXPECT_THROW(ss::elasticAverage(s.energy, {1.0, -1.0, 1.0}, s.ys, s.y2), de::InvalidInputError);
  EXPECT_THROW(ss::elasticAverage(s.energy, {0.0, 0.0, 0.0}, s.ys, s.y2), de::InvalidInputError);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(ss::elasticAverage(s.energy, {1.0, nan, 1.0}, s.ys, s.y2), de::InvalidInputError);
  Eigen::VectorXd bad = s.y1;
  bad[4] = nan;
  EXPECT_THROW(ss::elasticAverage(s.energy, s.w, {&s.y0, &bad, &s.y2}, s.y2), de::InvalidInputError);
  const Eigen::VectorXd shorter = s.y1.head(s.y1.size() - 3);
  EXPECT_THROW(ss::elasticAverage(s.energy, s.w, {&s.y0, &shorter, &s.y2}, s.y2), de::InvalidInputError);
}
