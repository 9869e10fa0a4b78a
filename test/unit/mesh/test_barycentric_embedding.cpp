#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/barycentric_embedding.hpp"
#include "deformation_enrichment/mesh/grid_tet_mesh.hpp"
#include "deformation_enrichment/mesh/tet_surface.hpp"

using namespace deformation_enrichment;

TEST(BarycentricEmbedding, FineSurfaceReproducesAffineDisplacementExactly) {
  // Graded coarse grid and a finer grid of the same box (its surface plays the fine surface), plus points
  // pushed slightly outside the coarse box to exercise the nearest-tet extension.
  Eigen::VectorXd xs(4), ys(3), zs(3);
  xs << -0.05, -0.01, 0.02, 0.05;
  ys << -0.05, 0.03, 0.05;
  zs << 0.0, 0.015, 0.02;
  const mesh::TetMesh coarse = mesh::gridTetMesh(xs, ys, zs);
  const mesh::TetMesh fine = mesh::gridTetMesh(Eigen::Vector3d(-0.05, -0.05, 0.0), Eigen::Vector3d(0.05, 0.05, 0.02),
                                               Eigen::Vector3i(9, 7, 5));
  Eigen::Matrix3Xd points = mesh::extractSurface(fine).surface.vertices;
  const Eigen::Index inside = points.cols();
  points.conservativeResize(3, inside + 2);
  points.col(inside) << 0.0501, 0.0, 0.01;
  points.col(inside + 1) << -0.02, 0.01, 0.0202;

  const mesh::BarycentricEmbedding embedding = mesh::embedPoints(coarse, points, 1e-3);
  EXPECT_LT(embedding.outside.head(inside).maxCoeff(), 1e-15);  // surface points: inside up to round-off
  EXPECT_NEAR(embedding.outside[inside], 1e-4, 1e-9);
  EXPECT_NEAR(embedding.outside[inside + 1], 2e-4, 1e-9);

  Eigen::Matrix3d A;
  A << 0.1, -0.3, 0.2, 0.05, 0.4, -0.1, 0.3, 0.0, -0.2;
  const Eigen::Vector3d b(0.01, -0.02, 0.005);
  const Eigen::Matrix3Xd coarseField = (A * coarse.vertices).colwise() + b;
  const Eigen::Matrix3Xd expected = (A * points).colwise() + b;
  const Eigen::Matrix3Xd interpolated = mesh::interpolate(embedding, coarse, coarseField);
  EXPECT_LT((interpolated - expected).cwiseAbs().maxCoeff(), 1e-15);
  for (Eigen::Index i = 0; i < embedding.weights.cols(); ++i) EXPECT_NEAR(embedding.weights.col(i).sum(), 1.0, 1e-14);
}

TEST(BarycentricEmbedding, RandomInteriorPointsAreInsideTheirTet) {
  const mesh::TetMesh coarse = mesh::gridTetMesh(Eigen::Vector3d::Zero(), Eigen::Vector3d(1, 2, 1), Eigen::Vector3i(3, 4, 2));
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Eigen::Matrix3Xd points(3, 500);
  for (Eigen::Index i = 0; i < points.cols(); ++i) points.col(i) << unit(rng), 2.0 * unit(rng), unit(rng);
  const mesh::BarycentricEmbedding embedding = mesh::embedPoints(coarse, points, 0.0);
  for (Eigen::Index i = 0; i < points.cols(); ++i) {
    EXPECT_GE(embedding.weights.col(i).minCoeff(), -1e-12);
    Eigen::Vector3d back = Eigen::Vector3d::Zero();
    for (int c = 0; c < 4; ++c) back += embedding.weights(c, i) * coarse.vertices.col(coarse.tets(c, embedding.tet[i]));
    EXPECT_LT((back - points.col(i)).norm(), 1e-14);
  }
}

TEST(BarycentricEmbedding, RejectsFarPointsNaNAndWrongFieldSize) {
  const mesh::TetMesh coarse = mesh::gridTetMesh(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(), Eigen::Vector3i(2, 2, 2));
  Eigen::Matrix3Xd far(3, 1);
  far << 3.0, 0.5, 0.5;
  EXPECT_THROW(mesh::embedPoints(coarse, far, 0.1), InvalidInputError);
  Eigen::Matrix3Xd nan(3, 1);
  nan << 0.5, std::nan(""), 0.5;
  EXPECT_THROW(mesh::embedPoints(coarse, nan, 0.1), InvalidInputError);
  Eigen::Matrix3Xd inside(3, 1);
  inside << 0.5, 0.5, 0.5;
  const auto embedding = mesh::embedPoints(coarse, inside, 0.0);
  EXPECT_THROW(mesh::interpolate(embedding, coarse, Eigen::Matrix3Xd::Zero(3, 5)), InvalidInputError);
}

TEST(BarycentricEmbedding, OutsidePointsExtendTheNearestTetAffinelyAndAreReported) {
  // SOFA-style extrapolation: an outside point's weights are its barycentric coordinates in the nearest
  // tet, some negative, and they reproduce the point itself (the identity is an affine field).
  const mesh::TetMesh coarse = mesh::gridTetMesh(Eigen::Vector3d::Zero(), Eigen::Vector3d(1, 2, 1), Eigen::Vector3i(2, 3, 2));
  Eigen::Matrix3Xd points(3, 5);
  points << 0.5, 1.03, 0.2, -0.01, 0.7,  //
      1.0, 1.5, -0.02, 1.0, 2.0,         //
      0.5, 0.5, 1.04, 0.3, 1.0;          // inside, beside x = 1, below y = 0 and above z = 1, beside x = 0, on an edge
  const mesh::BarycentricEmbedding embedding = mesh::embedPoints(coarse, points, 0.1);
  const Eigen::Matrix3Xd back = mesh::interpolate(embedding, coarse, coarse.vertices);
  EXPECT_LT((back - points).cwiseAbs().maxCoeff(), 1e-14);
  const double expected[] = {0.0, 0.03, std::hypot(0.02, 0.04), 0.01, 0.0};
  for (Eigen::Index i = 0; i < points.cols(); ++i) {
    EXPECT_NEAR(embedding.outside[i], expected[i], 1e-12) << i;
    if (expected[i] > 0.0) {
      EXPECT_LT(embedding.weights.col(i).minCoeff(), -1e-3) << i;
    }
  }
  EXPECT_EQ(embedding.report.outside, 3);  // the edge point is on the mesh (distance round-off at most)
  EXPECT_NEAR(embedding.report.maxDistance, std::hypot(0.02, 0.04), 1e-12);
  EXPECT_NEAR(embedding.report.meanDistance, (0.03 + std::hypot(0.02, 0.04) + 0.01) / 3.0, 1e-12);
  EXPECT_NE(mesh::describe(embedding.report, points.cols()).find("3 of 5 points outside"), std::string::npos);
}

TEST(BarycentricEmbedding, RefusalSaysHowManyAndHowFar) {
  const mesh::TetMesh coarse = mesh::gridTetMesh(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(), Eigen::Vector3i(3, 3, 3));
  Eigen::Matrix3Xd points(3, 4);
  points << 0.5, 1.5, 3.0, 1.05,  //
      0.5, 0.5, 0.5, 0.5,         //
      0.5, 0.5, 0.5, 0.5;
  try {
    mesh::embedPoints(coarse, points, 0.1);
    ADD_FAILURE() << "no error";
  } catch (const InvalidInputError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("2 of 4 points are farther than 0.1 m"), std::string::npos) << message;
    EXPECT_NE(message.find("point 2, is 2 m away"), std::string::npos) << message;
  }
}

TEST(BarycentricEmbedding, FarPointsAreLeftOutWhenAskedAndInterpolateToZero) {
  const mesh::TetMesh coarse = mesh::gridTetMesh(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(), Eigen::Vector3i(2, 2, 2));
  Eigen::Matrix3Xd points(3, 4);
  points << 0.5, 3.0, 1.05, 1.5,  //
      0.5, 0.5, 0.5, 0.5,         //
      0.5, 0.5, 0.5, 0.5;         // inside, far away, just outside (kept), outside beyond reach
  const mesh::BarycentricEmbedding embedding = mesh::embedPoints(coarse, points, 0.1, mesh::FarPoints::Skip);
  EXPECT_GE(embedding.tet[0], 0);
  EXPECT_EQ(embedding.tet[1], -1);
  EXPECT_GE(embedding.tet[2], 0);
  EXPECT_EQ(embedding.tet[3], -1);
  EXPECT_TRUE(std::isinf(embedding.outside[1]));
  EXPECT_NEAR(embedding.report.maxDistance, 0.05, 1e-12);  // left-out points are not in the report
  const Eigen::Matrix3Xd back = mesh::interpolate(embedding, coarse, coarse.vertices);
  EXPECT_LT((back.col(0) - points.col(0)).norm(), 1e-14);
  EXPECT_LT((back.col(2) - points.col(2)).norm(), 1e-14);  // the affine extension
  EXPECT_EQ(back.col(1), Eigen::Vector3d::Zero());
  EXPECT_EQ(back.col(3), Eigen::Vector3d::Zero());
  EXPECT_THROW(mesh::embedPoints(coarse, points, 0.1), InvalidInputError);  // the default still refuses
}
