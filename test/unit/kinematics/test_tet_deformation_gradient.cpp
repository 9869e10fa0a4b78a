#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>

#include <Eigen/Geometry>
#include <Eigen/LU>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/kinematics/mls_deformation_gradient.hpp"
#include "deformation_enrichment/kinematics/tet_deformation_gradient.hpp"
#include "deformation_enrichment/mesh/grid_tet_mesh.hpp"

using namespace deformation_enrichment;
using kinematics::Matrix34d;

namespace {
Matrix34d cornerTet() {
  Matrix34d X;
  X << 0, 1, 0, 0,  //
      0, 0, 1, 0,   //
      0, 0, 0, 1;
  return X;
}

// A smooth non-affine deformation phi and its gradient, for accuracy against ground truth.
Eigen::Vector3d phi(const Eigen::Vector3d& x) {
  return x + 0.2 * Eigen::Vector3d(std::sin(x[1]), x[0] * x[0], x[0] * x[2]);
}
Eigen::Matrix3d gradPhi(const Eigen::Vector3d& x) {
  Eigen::Matrix3d G = Eigen::Matrix3d::Identity();
  G(0, 1) += 0.2 * std::cos(x[1]);
  G(1, 0) += 0.4 * x[0];
  G(2, 0) += 0.2 * x[2];
  G(2, 2) += 0.2 * x[0];
  return G;
}
}  // namespace

TEST(TetDeformationGradient, ExactForAffineMapsAndIdentityAtRest) {
  std::srand(31);
  const Matrix34d X = cornerTet() + 0.1 * Matrix34d::Random();
  const Eigen::Matrix3d A = Eigen::Matrix3d::Identity() + 0.3 * Eigen::Matrix3d::Random();
  const Matrix34d x = (A * X).colwise() + Eigen::Vector3d(1, 2, 3);
  EXPECT_LT((kinematics::tetDeformationGradient(X, x) - A).norm(), 1e-13);
  EXPECT_LT((kinematics::tetDeformationGradient(X, X) - Eigen::Matrix3d::Identity()).norm(), 1e-14);
  // inverting the tet (mirror) is a result, not an error: det F < 0
  const Eigen::Matrix3d mirror = Eigen::Vector3d(1, 1, -1).asDiagonal();
  EXPECT_LT(kinematics::tetDeformationGradient(X, mirror * X).determinant(), 0.0);
  // the rest tet's orientation does not matter
  Matrix34d flipped = X;
  flipped.col(1).swap(flipped.col(2));
  Matrix34d xFlipped = x;
  xFlipped.col(1).swap(xFlipped.col(2));
  EXPECT_LT((kinematics::tetDeformationGradient(flipped, xFlipped) - A).norm(), 1e-13);
}

TEST(TetDeformationGradient, WholeMeshMatchesPerTetAndAffineMap) {
  const mesh::TetMesh grid = mesh::gridTetMesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 2, 1), Eigen::Vector3i(3, 4, 2));
  Eigen::Matrix3d A;
  A << 1.1, 0.2, 0.0,  //
      0.0, 0.9, 0.1,   //
      -0.3, 0.0, 1.2;
  const Eigen::Matrix3Xd deformed = A * grid.vertices;
  const auto F = kinematics::tetDeformationGradients(grid, deformed);
  ASSERT_EQ(static_cast<Eigen::Index>(F.size()), grid.numTets());
  for (const auto& Ft : F) EXPECT_LT((Ft - A).norm(), 1e-12);

  // a non-affine map: each tet's F equals the single-tet function's and approximates grad phi at the
  // tet centroid to O(edge length)
  Eigen::Matrix3Xd curved(3, grid.numVertices());
  for (Eigen::Index v = 0; v < grid.numVertices(); ++v) curved.col(v) = phi(grid.vertices.col(v));
  const auto inverses = kinematics::restShapeInverses(grid);
  const auto Fcurved = kinematics::tetDeformationGradients(grid, inverses, curved);
  for (Eigen::Index t = 0; t < grid.numTets(); ++t) {
    Matrix34d X, x;
    for (int k = 0; k < 4; ++k) {
      X.col(k) = grid.vertices.col(grid.tets(k, t));
      x.col(k) = curved.col(grid.tets(k, t));
    }
    EXPECT_LT((kinematics::tetDeformationGradient(X, x) - Fcurved[static_cast<size_t>(t)]).norm(), 1e-13);
    EXPECT_LT((Fcurved[static_cast<size_t>(t)] - gradPhi(X.rowwise().mean())).norm(), 0.2);
  }
}

TEST(TetDeformationGradient, BadInputThrows) {
  Matrix34d flat = cornerTet();
  flat(2, 3) = 0.0;  // all four vertices in z = 0
  EXPECT_THROW(kinematics::tetDeformationGradient(flat, flat), InvalidInputError);
  EXPECT_THROW(kinematics::restShapeInverse(Matrix34d::Zero()), InvalidInputError);
  Matrix34d nan = cornerTet();
  nan(0, 2) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(kinematics::tetDeformationGradient(nan, cornerTet()), InvalidInputError);
  EXPECT_THROW(kinematics::tetDeformationGradient(cornerTet(), nan), InvalidInputError);

  const mesh::TetMesh grid = mesh::gridTetMesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 1, 1), Eigen::Vector3i(2, 2, 2));
  EXPECT_THROW(kinematics::tetDeformationGradients(grid, grid.vertices.leftCols(5)), InvalidInputError);
  Eigen::Matrix3Xd bad = grid.vertices;
  bad(1, 4) = std::numeric_limits<double>::infinity();
  EXPECT_THROW(kinematics::tetDeformationGradients(grid, bad), InvalidInputError);
  EXPECT_THROW(kinematics::tetDeformationGradients(grid, kinematics::Matrix3dList(3), grid.vertices),
               InvalidInputError);
  mesh::TetMesh degenerate = grid;
  degenerate.vertices.col(degenerate.tets(1, 0)) = degenerate.vertices.col(degenerate.tets(0, 0));
  EXPECT_THROW(kinematics::restShapeInverses(degenerate), InvalidInputError);
}

// MLS F of a smooth non-affine map on a regular point grid, against the analytic gradient: with
// samples symmetric about p the weighted centroid is p and the error is second order in the window h.
TEST(MlsDeformationGradient, ConvergesToAnalyticGradientOfNonAffineMap) {
  const Eigen::Vector3d p(0.3, -0.2, 0.5);
  double previousError = 0.0;
  for (double h : {0.2, 0.1, 0.05}) {
    const double spacing = h / 4.0;
    const int half = 16;  // samples out to 4 h
    const int side = 2 * half + 1;
    Eigen::Matrix3Xd x(3, side * side * side), y(3, side * side * side);
    Eigen::VectorXd w(side * side * side);
    int m = 0;
    for (int i = -half; i <= half; ++i)
      for (int j = -half; j <= half; ++j)
        for (int k = -half; k <= half; ++k, ++m) {
          x.col(m) = p + spacing * Eigen::Vector3d(i, j, k);
          y.col(m) = phi(x.col(m));
          w[m] = std::exp(-0.5 * (x.col(m) - p).squaredNorm() / (h * h));
        }
    const auto r = kinematics::mlsDeformationGradient(x, y, w);
    EXPECT_LT((r.xBar - p).norm(), 1e-12);
    const double error = (r.F - gradPhi(p)).norm();
    std::printf("MLS F error at h = %.3f: %.3e\n", h, error);
    EXPECT_LT(error, 0.2 * h * h);
    if (previousError > 0.0) {
      EXPECT_LT(error, 0.3 * previousError);  // second order: ratio ~ 1/4
    }
    previousError = error;
  }
}
