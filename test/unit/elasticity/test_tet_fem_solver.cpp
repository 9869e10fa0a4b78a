// Paper 001's stabilities (§3.2.1: inversion, rest, meta-stability under degeneracy) as solver stress
// tests: crushed, collapsed, inverted and twisted blocks return to the rest shape once released (bottom
// face held); random scrambles never give NaN.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <cstdio>
#include <random>

#include "deformation_enrichment/elasticity/quasi_static_solver.hpp"
#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/grid_tet_mesh.hpp"

using namespace deformation_enrichment;
using namespace deformation_enrichment::elasticity;

namespace {

constexpr double kSize = 0.02;  // 2 cm cube

struct Block {
  TetFem fem;
  DirichletConstraints support;  ///< bottom face at rest
  std::vector<int> freeVertices;
};

Block makeBlock(SnhVariant variant, int cells = 3, double poisson = 0.45) {
  const mesh::TetMesh m = mesh::gridTetMesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(kSize, kSize, kSize), Eigen::Vector3i(cells, cells, cells));
  const auto lame = lameFromYoungPoisson(1e4, poisson);
  Block block{TetFem(m, StableNeoHookean(lame.mu, lame.lambda, variant)), {}, {}};
  for (Eigen::Index v = 0; v < m.numVertices(); ++v) {
    if (m.vertices(2, v) == 0.0)
      block.support.add(static_cast<int>(v), m.vertices.col(v));
    else
      block.freeVertices.push_back(static_cast<int>(v));
  }
  return block;
}

/// Releases `start` (bottom face held) and expects the rest shape back.
void expectRecovers(const Block& block, Eigen::Matrix3Xd start, const std::string& what) {
  SolverOptions settings;
  settings.maxIterations = 200;
  settings.relativeForceTolerance = 1e-12;  // starts far from rest have |f_0| ~ 1e4 N
  QuasiStaticSolver solver(block.fem, settings);
  const SolveResult result = solver.solve(start, block.support);
  EXPECT_TRUE(result.converged()) << what << ": " << result.message;
  EXPECT_TRUE(start.allFinite()) << what;
  const double error = (start - block.fem.rest().vertices).cwiseAbs().maxCoeff();
  EXPECT_LT(error, 1e-6 * kSize) << what << ": " << result.message;
  int inverted = 0;
  for (Eigen::Index t = 0; t < block.fem.numTets(); ++t) inverted += block.fem.deformationGradient(start, t).determinant() <= 0.0;
  EXPECT_EQ(inverted, 0) << what;
}

class SolverStress : public testing::TestWithParam<SnhVariant> {};

}  // namespace

TEST_P(SolverStress, CrushedToAPlaneRecovers) {
  const Block block = makeBlock(GetParam());
  Eigen::Matrix3Xd x = block.fem.rest().vertices;
  x.row(2).setZero();  // every tet flat: J = 0
  expectRecovers(block, x, "plane");
}

TEST_P(SolverStress, CrushedToANearPointRecovers) {
  const Block block = makeBlock(GetParam());
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> jitter(-1e-7, 1e-7);
  Eigen::Matrix3Xd x = block.fem.rest().vertices;
  for (int v : block.freeVertices) x.col(v) = Eigen::Vector3d(0.01 + jitter(rng), 0.01 + jitter(rng), jitter(rng));
  expectRecovers(block, x, "near-point");
}

TEST_P(SolverStress, InvertedThroughTheSupportRecovers) {
  const Block block = makeBlock(GetParam());
  Eigen::Matrix3Xd x = block.fem.rest().vertices;
  x.row(2) *= -1.0;  // mirror through the bottom plane: every tet inverted
  expectRecovers(block, x, "inverted");
}

TEST_P(SolverStress, TwistedBlockRecovers) {
  const Block block = makeBlock(GetParam(), 4);
  Eigen::Matrix3Xd x = block.fem.rest().vertices;
  for (Eigen::Index v = 0; v < x.cols(); ++v) {
    // Twist by 1.5 turns about the vertical axis through the centre, growing linearly with height.
    const double angle = 3.0 * M_PI * x(2, v) / kSize;
    const Eigen::Vector3d centre(kSize / 2, kSize / 2, 0.0);
    x.col(v) = centre + Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitZ()) * (x.col(v) - centre);
  }
  expectRecovers(block, x, "twisted");
}

TEST_P(SolverStress, RandomPerturbationsRecover) {
  // Noise of half a cell (many tets inverted) is undone completely.
  const Block block = makeBlock(GetParam());
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0.0, 0.5 * kSize / 3);
  for (int trial = 0; trial < 4; ++trial) {
    Eigen::Matrix3Xd x = block.fem.rest().vertices;
    for (int v : block.freeVertices) x.col(v) += Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
    expectRecovers(block, x, "perturbation " + std::to_string(trial));
  }
}

TEST_P(SolverStress, RandomScramblesNeverGiveNaN) {
  // Free vertices thrown anywhere in a box three times the block: the solver always reaches an
  // equilibrium with finite positions and lower energy. Not every scramble untangles to the rest shape
  // (some settle in another strict local minimum with E > 0 and no inverted tet), so recovery is
  // counted, not required.
  const Block block = makeBlock(GetParam());
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> anywhere(-kSize, 2.0 * kSize);
  SolverOptions settings;
  settings.maxIterations = 300;
  settings.relativeForceTolerance = 1e-10;
  QuasiStaticSolver solver(block.fem, settings);
  int recovered = 0;
  for (int trial = 0; trial < 8; ++trial) {
    Eigen::Matrix3Xd x = block.fem.rest().vertices;
    for (int v : block.freeVertices) x.col(v) = Eigen::Vector3d(anywhere(rng), anywhere(rng), anywhere(rng));
    const double startEnergy = block.fem.energy(x);
    const SolveResult result = solver.solve(x, block.support);
    EXPECT_TRUE(result.converged()) << result.message;
    EXPECT_TRUE(x.allFinite());
    EXPECT_TRUE(std::isfinite(result.energy));
    EXPECT_LT(result.energy, startEnergy);
    recovered += (x - block.fem.rest().vertices).cwiseAbs().maxCoeff() < 1e-6 * kSize;
    // Wherever it settles, it is a strict local minimum (exact Hessian of the free dofs positive
    // definite), not a saddle the projection got stuck on.
    const Eigen::VectorXi map = makeDofMap(x.cols(), block.support.vertices);
    Eigen::SparseMatrix<double> H = block.fem.reducedPattern(map, false);
    block.fem.assembleReduced(x, map, false, HessianKind::Exact, H, nullptr);
    const Eigen::VectorXd eigenvalues = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(Eigen::MatrixXd(H)).eigenvalues();
    EXPECT_GT(eigenvalues.minCoeff(), 1e-6 * eigenvalues.maxCoeff()) << "trial " << trial;
  }
  RecordProperty("recovered_of_8", recovered);
  std::printf("scrambles that returned to rest: %d of 8\n", recovered);
}

INSTANTIATE_TEST_SUITE_P(BothVariants, SolverStress, testing::Values(SnhVariant::Paper, SnhVariant::Production));

TEST(QuasiStaticSolver, PrescribedTopMatchesLinearElasticityForSmallStretch) {
  // Bar pulled by a small strain with lateral contraction free: the reaction force over the top face
  // must equal E * strain * area (the SNH reparametrisation reproduces linear elasticity), and the
  // callback reports monotone energy decrease.
  const Block block = makeBlock(SnhVariant::Paper, 3, 0.3);
  DirichletConstraints constraints = block.support;
  const double strain = 1e-4;
  std::vector<int> top;
  for (int v : block.freeVertices)
    if (block.fem.rest().vertices(2, v) == kSize) top.push_back(v);
  // Top face clamped in x, y (like the bottom), pulled in z: uniaxial-strain is not exact with clamped
  // faces, so compare against the slightly stiffer bound range instead of one value.
  for (int v : top) constraints.add(v, block.fem.rest().vertices.col(v) + Eigen::Vector3d(0, 0, strain * kSize));
  std::vector<double> energies;
  SolverOptions settings;
  settings.callback = [&](const IterationRecord& record) { energies.push_back(record.energy); };
  QuasiStaticSolver solver(block.fem, settings);
  Eigen::Matrix3Xd x = block.fem.rest().vertices;
  const SolveResult result = solver.solve(x, constraints);
  ASSERT_TRUE(result.converged()) << result.message;
  ASSERT_FALSE(energies.empty());
  // Monotone up to the round-off of E (steps below it are accepted on the force norm instead).
  const double roundOff = 1e-14 * block.fem.maxShearModulus() * block.fem.restVolumes().sum();
  for (std::size_t k = 1; k < energies.size(); ++k) EXPECT_LE(energies[k], energies[k - 1] * (1 + 1e-12) + roundOff);
  const Eigen::VectorXd g = block.fem.gradient(x);
  double reaction = 0.0;
  for (int v : top) reaction += g[3 * v + 2];
  const double E = 1e4, nu = 0.3, area = kSize * kSize;
  const double uniaxialStress = E * strain * area;                                          // free sides
  const double confinedStress = E * (1 - nu) / ((1 + nu) * (1 - 2 * nu)) * strain * area;  // no lateral strain
  EXPECT_GT(reaction, uniaxialStress);
  EXPECT_LT(reaction, confinedStress);
}

TEST(QuasiStaticSolver, ReportsLimitsAndRejectsBadInput) {
  const Block block = makeBlock(SnhVariant::Production);
  Eigen::Matrix3Xd x = block.fem.rest().vertices;
  x.row(2) *= -1.0;
  SolverOptions settings;
  settings.maxIterations = 2;
  QuasiStaticSolver limited(block.fem, settings);
  Eigen::Matrix3Xd copy = x;
  const SolveResult result = limited.solve(copy, block.support);
  EXPECT_EQ(result.status, SolverStatus::MaxIterations);
  EXPECT_FALSE(result.converged());
  EXPECT_NE(result.message.find("iteration limit"), std::string::npos);
  EXPECT_TRUE(copy.allFinite());
  EXPECT_LT(result.energy, block.fem.energy(x));

  SolverOptions bad;
  bad.reuseContraction = 1.5;
  EXPECT_THROW(QuasiStaticSolver(block.fem, bad), InvalidInputError);
  bad = SolverOptions();
  bad.armijo = 0.0;
  EXPECT_THROW(QuasiStaticSolver(block.fem, bad), InvalidInputError);
  bad = SolverOptions();
  bad.preconditionedTolerance = 1.0;
  EXPECT_THROW(QuasiStaticSolver(block.fem, bad), InvalidInputError);
  bad = SolverOptions();
  bad.preconditionedIterations = -1;
  EXPECT_THROW(QuasiStaticSolver(block.fem, bad), InvalidInputError);
  QuasiStaticSolver solver(block.fem);
  Eigen::Matrix3Xd wrong = Eigen::Matrix3Xd::Zero(3, 2);
  EXPECT_THROW(solver.solve(wrong, block.support), InvalidInputError);
  Eigen::Matrix3Xd nan = x;
  nan(0, 5) = std::nan("");
  EXPECT_THROW(solver.solve(nan, block.support), InvalidInputError);
  DirichletConstraints twice = block.support;
  twice.add(block.support.vertices[0], Eigen::Vector3d::Zero());
  EXPECT_THROW(solver.solve(x, twice), InvalidInputError);
  DirichletConstraints outOfRange;
  outOfRange.add(100000, Eigen::Vector3d::Zero());
  EXPECT_THROW(solver.solve(x, outOfRange), InvalidInputError);
  DirichletConstraints all;
  for (Eigen::Index v = 0; v < x.cols(); ++v) all.add(static_cast<int>(v), x.col(v));
  EXPECT_THROW(solver.solve(x, all), InvalidInputError);
}

TEST(QuasiStaticSolver, CholmodAndLdltAgree) {
#ifdef DE_HAVE_CHOLMOD
  const Block block = makeBlock(SnhVariant::Paper);
  Eigen::Matrix3Xd a = block.fem.rest().vertices;
  a.row(2) *= 0.5;
  Eigen::Matrix3Xd b = a;
  SolverOptions settings;
  settings.linearSolver = numerics::SparseCholeskyBackend::Cholmod;
  QuasiStaticSolver cholmod(block.fem, settings);
  settings.linearSolver = numerics::SparseCholeskyBackend::EigenSimplicial;
  QuasiStaticSolver ldlt(block.fem, settings);
  DirichletConstraints constraints = block.support;
  constraints.add(block.freeVertices.back(), a.col(block.freeVertices.back()));
  ASSERT_TRUE(cholmod.solve(a, constraints).converged());
  ASSERT_TRUE(ldlt.solve(b, constraints).converged());
  EXPECT_LT((a - b).cwiseAbs().maxCoeff(), 1e-9 * kSize);
#else
  GTEST_SKIP() << "built without CHOLMOD";
#endif
}

TEST(QuasiStaticSolver, PreconditionedDirectionsSaveFactorisationsAndReachTheSameState) {
  // A 6 mm press into a 2 cm block: the projected Newton phase lasts several iterations, which conjugate
  // gradients preconditioned by the first factorisation take instead of new factorisations.
  const Block block = makeBlock(SnhVariant::Paper, 6);
  const int top = block.freeVertices.back();
  DirichletConstraints press = block.support;
  press.add(top, block.fem.rest().vertices.col(top) + Eigen::Vector3d(0.002, 0.0, -0.006));
  SolverOptions factorising;
  factorising.preconditionedTolerance = 0.0;
  Eigen::Matrix3Xd x = block.fem.rest().vertices, y = x;
  const SolveResult inexact = QuasiStaticSolver(block.fem).solve(x, press);
  const SolveResult exact = QuasiStaticSolver(block.fem, factorising).solve(y, press);
  ASSERT_TRUE(inexact.converged()) << inexact.message;
  ASSERT_TRUE(exact.converged()) << exact.message;
  int preconditioned = 0;
  for (const IterationRecord& r : inexact.history) preconditioned += r.conjugateGradientIterations > 0;
  for (const IterationRecord& r : exact.history) EXPECT_EQ(r.conjugateGradientIterations, 0);
  EXPECT_GT(preconditioned, 0);
  EXPECT_LT(inexact.factorizations, exact.factorizations);
  EXPECT_LT((x - y).cwiseAbs().maxCoeff(), 1e-8 * kSize);
}

TEST(QuasiStaticSolver, ReusedSolverFollowsChangingConstraintSets) {
  // The same solver object re-analyses when the constrained vertex set changes (a tool moving onto
  // other vertices); its answers must equal those of a fresh solver, within what the force tolerance
  // (1e-8 of the initial force) leaves of the displacement.
  const Block block = makeBlock(SnhVariant::Paper);
  const int a = block.freeVertices.back(), b = block.freeVertices[block.freeVertices.size() / 2];
  DirichletConstraints first = block.support, second = block.support;
  first.add(a, block.fem.rest().vertices.col(a) + Eigen::Vector3d(0, 0, -0.004));
  second.add(b, block.fem.rest().vertices.col(b) + Eigen::Vector3d(0.002, 0, -0.003));
  QuasiStaticSolver reused(block.fem);
  Eigen::Matrix3Xd x = block.fem.rest().vertices;
  ASSERT_TRUE(reused.solve(x, first).converged());
  ASSERT_TRUE(reused.solve(x, second).converged());
  QuasiStaticSolver fresh(block.fem);
  Eigen::Matrix3Xd y = block.fem.rest().vertices;
  ASSERT_TRUE(fresh.solve(y, second).converged());
  EXPECT_LT((x - y).cwiseAbs().maxCoeff(), 1e-8 * kSize);
}
