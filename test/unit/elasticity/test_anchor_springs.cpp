// Penalty anchors: gradient against finite differences, validation, and in the solver a very stiff
// spring reproduces the Dirichlet solution of the same prescribed position.
#include <gtest/gtest.h>

#include "deformation_enrichment/elasticity/anchor_springs.hpp"
#include "deformation_enrichment/elasticity/quasi_static_solver.hpp"
#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/grid_tet_mesh.hpp"

using namespace deformation_enrichment;
using namespace deformation_enrichment::elasticity;

namespace {

AnchorSprings twoSprings() {
  AnchorSprings s;
  s.vertices = {1, 3};
  s.stiffness = Eigen::Vector2d(2.0, 5.0);
  s.targets = Eigen::Matrix<double, 3, 2>::Random();
  return s;
}

}  // namespace

TEST(AnchorSprings, GradientMatchesFiniteDifferences) {
  const AnchorSprings s = twoSprings();
  const Eigen::Matrix3Xd x = Eigen::Matrix3Xd::Random(3, 4);
  Eigen::VectorXd g = Eigen::VectorXd::Zero(12);
  s.addGradient(x, g);
  const double h = 1e-6;
  for (int d = 0; d < 12; ++d) {
    Eigen::Matrix3Xd plus = x, minus = x;
    plus(d % 3, d / 3) += h;
    minus(d % 3, d / 3) -= h;
    EXPECT_NEAR(g[d], (s.energy(plus) - s.energy(minus)) / (2 * h), 1e-8) << "dof " << d;
  }
  EXPECT_EQ(g.segment<3>(0).norm(), 0.0);  // unanchored vertices feel nothing
}

TEST(AnchorSprings, RejectsBadSprings) {
  AnchorSprings s = twoSprings();
  EXPECT_NO_THROW(s.validate(4));
  EXPECT_THROW(s.validate(3), InvalidInputError);  // vertex 3 out of range
  s.vertices = {1, 1};
  EXPECT_THROW(s.validate(4), InvalidInputError);  // repeated
  s = twoSprings();
  s.stiffness[0] = -1.0;
  EXPECT_THROW(s.validate(4), InvalidInputError);
  s = twoSprings();
  s.targets(0, 1) = std::nan("");
  EXPECT_THROW(s.validate(4), InvalidInputError);
  s = twoSprings();
  s.stiffness.resize(1);
  EXPECT_THROW(s.validate(4), InvalidInputError);
}

TEST(AnchorSprings, StiffSpringReproducesDirichletPull) {
  const mesh::TetMesh rest = mesh::gridTetMesh(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.02, 0.02, 0.01), Eigen::Vector3i(4, 4, 2));
  const TetFem fem(rest, StableNeoHookean(1e4, 4e4));
  DirichletConstraints support;
  std::vector<int> top;
  for (Eigen::Index v = 0; v < rest.numVertices(); ++v) {
    if (rest.vertices(2, v) == 0.0) support.add(static_cast<int>(v), rest.vertices.col(v));
    if (rest.vertices(2, v) == 0.01 && std::abs(rest.vertices(0, v) - 0.01) < 1e-9 && std::abs(rest.vertices(1, v) - 0.01) < 1e-9)
      top.push_back(static_cast<int>(v));
  }
  ASSERT_EQ(top.size(), 1u);
  const Eigen::Vector3d target = rest.vertices.col(top[0]) + Eigen::Vector3d(0.001, 0.0, -0.002);

  DirichletConstraints pulled = support;
  pulled.add(top[0], target);
  Eigen::Matrix3Xd dirichlet = rest.vertices;
  ASSERT_TRUE(QuasiStaticSolver(fem).solve(dirichlet, pulled).converged());

  AnchorSprings spring;
  spring.vertices = top;
  spring.stiffness = Eigen::VectorXd::Constant(1, 1e9);
  spring.targets = target;
  Eigen::Matrix3Xd penalty = rest.vertices;
  const SolveResult r = QuasiStaticSolver(fem).solve(penalty, support, spring);
  ASSERT_TRUE(r.converged()) << r.message;
  // The spring force ~ 1e9 * slip balances the body's ~O(10 N/m) stiffness: slip and every vertex agree
  // with the Dirichlet solution to well below a micrometre.
  EXPECT_LT((penalty - dirichlet).cwiseAbs().maxCoeff(), 1e-7);
  EXPECT_GT((penalty.col(top[0]) - rest.vertices.col(top[0])).norm(), 0.002);
}
