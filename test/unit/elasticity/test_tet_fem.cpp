#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <random>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "deformation_enrichment/elasticity/tet_fem.hpp"
#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/grid_tet_mesh.hpp"

using namespace deformation_enrichment;
using elasticity::HessianKind;
using elasticity::SnhVariant;
using elasticity::StableNeoHookean;
using elasticity::TetFem;

namespace {

/// 2 x 2 x 2 cells of a 2 cm box, two materials (stiff top cells over soft bottom ones).
TetFem twoMaterialBlock(SnhVariant variant) {
  const mesh::TetMesh m = mesh::gridTetMesh(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.02, 0.02, 0.02), Eigen::Vector3i(2, 2, 2));
  Eigen::VectorXi id(m.numTets());
  for (Eigen::Index t = 0; t < m.numTets(); ++t) id[t] = m.vertices(2, m.tets(0, t)) > 0.009 ? 1 : 0;
  const auto soft = elasticity::lameFromYoungPoisson(1e4, 0.45);
  const auto stiff = elasticity::lameFromYoungPoisson(3e5, 0.3);
  return TetFem(m, {StableNeoHookean(soft.mu, soft.lambda, variant), StableNeoHookean(stiff.mu, stiff.lambda, variant)}, id);
}

/// Rest positions plus noise of `scale` metres (large enough to invert some tets).
Eigen::Matrix3Xd perturbed(const TetFem& fem, double scale, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, scale);
  Eigen::Matrix3Xd x = fem.rest().vertices;
  for (Eigen::Index i = 0; i < x.size(); ++i) x.data()[i] += noise(rng);
  return x;
}

int invertedTets(const TetFem& fem, const Eigen::Matrix3Xd& x) {
  int count = 0;
  for (Eigen::Index t = 0; t < fem.numTets(); ++t) count += fem.deformationGradient(x, t).determinant() < 0.0;
  return count;
}

class TetFemDerivatives : public testing::TestWithParam<SnhVariant> {};

}  // namespace

TEST_P(TetFemDerivatives, GradientMatchesCentralDifferencesOfEnergy) {
  const TetFem fem = twoMaterialBlock(GetParam());
  for (unsigned seed = 1; seed <= 3; ++seed) {
    Eigen::Matrix3Xd x = perturbed(fem, 0.004, seed);
    if (seed == 3) {
      EXPECT_GT(invertedTets(fem, x), 0);
    }
    const Eigen::VectorXd g = fem.gradient(x);
    Eigen::VectorXd fd(g.size());
    const double h = 1e-7;
    for (Eigen::Index d = 0; d < g.size(); ++d) {
      const double keep = x.data()[d];
      x.data()[d] = keep + h;
      const double plus = fem.energy(x);
      x.data()[d] = keep - h;
      const double minus = fem.energy(x);
      x.data()[d] = keep;
      fd[d] = (plus - minus) / (2.0 * h);
    }
    EXPECT_LT((fd - g).norm(), 1e-6 * g.norm()) << "seed " << seed;
  }
}

TEST_P(TetFemDerivatives, ExactHessianMatchesCentralDifferencesOfGradient) {
  const TetFem fem = twoMaterialBlock(GetParam());
  for (unsigned seed = 4; seed <= 6; ++seed) {
    Eigen::Matrix3Xd x = perturbed(fem, 0.004, seed);
    const Eigen::MatrixXd H = Eigen::MatrixXd(fem.hessian(x, HessianKind::Exact));
    Eigen::MatrixXd fd(H.rows(), H.cols());
    const double h = 1e-7;
    for (Eigen::Index d = 0; d < H.cols(); ++d) {
      const double keep = x.data()[d];
      x.data()[d] = keep + h;
      const Eigen::VectorXd plus = fem.gradient(x);
      x.data()[d] = keep - h;
      const Eigen::VectorXd minus = fem.gradient(x);
      x.data()[d] = keep;
      fd.col(d) = (plus - minus) / (2.0 * h);
    }
    EXPECT_LT((fd - H).norm(), 1e-6 * H.norm()) << "seed " << seed;
    EXPECT_LT((H - H.transpose()).norm(), 1e-12 * H.norm());
  }
}

TEST_P(TetFemDerivatives, ProjectedHessianIsPsdAndExactNearRest) {
  const TetFem fem = twoMaterialBlock(GetParam());
  // Far from rest with inverted tets: the projection must leave no negative eigenvalue, while the exact
  // Hessian does have some (otherwise the test would prove nothing).
  const Eigen::Matrix3Xd far = perturbed(fem, 0.006, 9);
  ASSERT_GT(invertedTets(fem, far), 0);
  const Eigen::MatrixXd exact = Eigen::MatrixXd(fem.hessian(far, HessianKind::Exact));
  const Eigen::MatrixXd projected = Eigen::MatrixXd(fem.hessian(far, HessianKind::Projected));
  const double scale = exact.norm();
  EXPECT_LT(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(exact).eigenvalues().minCoeff(), -1e-3 * scale);
  EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(projected).eigenvalues().minCoeff(), -1e-12 * scale);
  // At rest every element Hessian is the (PSD) linear-elasticity tensor, so projection changes nothing
  // beyond round-off (its rotation modes have eigenvalue zero; any strain can tip them negative).
  const Eigen::Matrix3Xd near = fem.rest().vertices;
  const Eigen::MatrixXd exactNear = Eigen::MatrixXd(fem.hessian(near, HessianKind::Exact));
  const Eigen::MatrixXd projectedNear = Eigen::MatrixXd(fem.hessian(near, HessianKind::Projected));
  EXPECT_LT((exactNear - projectedNear).norm(), 1e-10 * exactNear.norm());
}

INSTANTIATE_TEST_SUITE_P(BothVariants, TetFemDerivatives, testing::Values(SnhVariant::Paper, SnhVariant::Production));

TEST(TetFem, RestStateHasZeroEnergyAndForceAndTranslationInvariance) {
  const TetFem fem = twoMaterialBlock(SnhVariant::Paper);
  EXPECT_EQ(fem.energy(fem.rest().vertices), 0.0);
  EXPECT_EQ(fem.gradient(fem.rest().vertices).cwiseAbs().maxCoeff(), 0.0);
  // A rigid motion costs nothing and exerts no force (up to round-off).
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  const Eigen::Matrix3Xd moved = (R * fem.rest().vertices).colwise() + Eigen::Vector3d(0.1, -0.2, 0.3);
  EXPECT_NEAR(fem.energy(moved), 0.0, 1e-15);
  const Eigen::Matrix3Xd x = perturbed(fem, 0.002, 11);
  const Eigen::VectorXd g = fem.gradient(x);
  // Net force and net torque of internal forces vanish.
  Eigen::Vector3d force = Eigen::Vector3d::Zero(), torque = Eigen::Vector3d::Zero();
  for (Eigen::Index v = 0; v < fem.numVertices(); ++v) {
    force += g.segment<3>(3 * v);
    torque += x.col(v).cross(g.segment<3>(3 * v));
  }
  EXPECT_LT(force.norm(), 1e-12 * g.norm());
  EXPECT_LT(torque.norm(), 1e-12 * g.norm() * 0.03);
}

TEST(TetFem, ReducedAssemblyIsTheFreeBlockOfTheFullHessian) {
  const TetFem fem = twoMaterialBlock(SnhVariant::Production);
  const Eigen::Matrix3Xd x = perturbed(fem, 0.003, 12);
  const std::vector<int> fixed{0, 4, 9, 17};
  int freeCount = 0;
  const Eigen::VectorXi map = elasticity::makeDofMap(fem.numVertices(), fixed, &freeCount);
  EXPECT_EQ(freeCount, 3 * (static_cast<int>(fem.numVertices()) - 4));
  Eigen::SparseMatrix<double> lower = fem.reducedPattern(map, true);
  Eigen::VectorXd g;
  fem.assembleReduced(x, map, true, HessianKind::Projected, lower, &g);
  const Eigen::MatrixXd full = Eigen::MatrixXd(fem.hessian(x));
  const Eigen::VectorXd fullGradient = fem.gradient(x);
  const Eigen::MatrixXd reduced = Eigen::MatrixXd(Eigen::SparseMatrix<double>(lower.selfadjointView<Eigen::Lower>()));
  for (Eigen::Index a = 0; a < map.size(); ++a) {
    if (map[a] < 0) continue;
    EXPECT_NEAR(g[map[a]], fullGradient[a], 1e-12 * fullGradient.norm());
    for (Eigen::Index b = 0; b < map.size(); ++b)
      if (map[b] >= 0) {
        ASSERT_NEAR(reduced(map[a], map[b]), full(a, b), 1e-12 * full.norm());
      }
  }
}

TEST(TetFem, RejectsBadInput) {
  const mesh::TetMesh m = mesh::gridTetMesh(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(), Eigen::Vector3i(1, 1, 1));
  const StableNeoHookean material(1.0, 10.0);
  EXPECT_THROW(TetFem(m, {material}, Eigen::VectorXi::Zero(2)), InvalidInputError);
  EXPECT_THROW(TetFem(m, {material}, Eigen::VectorXi::Constant(m.numTets(), 1)), InvalidInputError);
  EXPECT_THROW(TetFem(m, std::vector<StableNeoHookean>{}, Eigen::VectorXi::Zero(m.numTets())), InvalidInputError);
  mesh::TetMesh flat = m;
  flat.vertices.row(2).setZero();
  EXPECT_THROW(TetFem(flat, material), InvalidInputError);
  const TetFem fem(m, material);
  EXPECT_THROW(fem.energy(Eigen::Matrix3Xd::Zero(3, 3)), InvalidInputError);
  Eigen::Matrix3Xd nan = m.vertices;
  nan(1, 2) = std::nan("");
  EXPECT_EQ(fem.energy(nan), std::numeric_limits<double>::infinity());
  EXPECT_THROW(fem.gradient(nan), InvalidInputError);
  EXPECT_THROW(fem.hessian(nan), InvalidInputError);
  EXPECT_THROW(elasticity::makeDofMap(8, {8}), InvalidInputError);
}

// Parallel assembly colours the tets instead of adding atomically: the energy, gradient and Hessian of a
// mesh large enough to run in parallel are the same bits on one thread and on three.
TEST(TetFem, AssemblyIsTheSameBitsOnAnyNumberOfThreads) {
  const mesh::TetMesh m = mesh::gridTetMesh(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.1, 0.1, 0.05), Eigen::Vector3i(10, 10, 5));
  ASSERT_GT(m.numTets(), 2000);  // the parallel path
  const auto lame = elasticity::lameFromYoungPoisson(1e4, 0.45);
  const TetFem fem(m, StableNeoHookean(lame.mu, lame.lambda, SnhVariant::Production));
  const Eigen::Matrix3Xd x = perturbed(fem, 0.002, 7);
  struct Assembly {
    double energy;
    Eigen::VectorXd gradient;
    Eigen::SparseMatrix<double> hessian;
  };
  const auto assemble = [&](int threads) {
#ifdef _OPENMP
    omp_set_num_threads(threads);
#else
    (void)threads;
#endif
    return Assembly{fem.energy(x), fem.gradient(x), fem.hessian(x, HessianKind::Projected)};
  };
  const Assembly one = assemble(1), three = assemble(3);
#ifdef _OPENMP
  omp_set_num_threads(omp_get_num_procs());
#endif
  EXPECT_EQ(one.energy, three.energy);
  EXPECT_TRUE(one.gradient == three.gradient);
  ASSERT_EQ(one.hessian.nonZeros(), three.hessian.nonZeros());
  EXPECT_TRUE(std::equal(one.hessian.valuePtr(), one.hessian.valuePtr() + one.hessian.nonZeros(), three.hessian.valuePtr()));
}
