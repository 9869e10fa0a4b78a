#include <gtest/gtest.h>

#include <limits>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <Eigen/LU>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/kinematics/triangle_deformation_gradient.hpp"
#include "random_rotation.hpp"

using namespace deformation_enrichment;
using kinematics::triangleDeformationGradient;

namespace {

// Seed 003's triangle (face 0 of the log, eqs. 5-8). The log's F (eq. 13) puts the edges of the VertT
// vertices in the numerator, so VertR is the rest ("reference") triangle and VertT the deformed one.
// (Its eqs. 10-11 swap the labels: the numbers printed as "VecT" are the VertR edges and vice versa.)
const Eigen::Vector3d kVertR[3] = {{0.759919, -0.015194, 6.38401},
                                   {0.767822, -0.0212492, 6.3669},
                                   {0.726977, -0.00749985, 6.38692}};
const Eigen::Vector3d kVertT[3] = {{0.771842, -0.0144887, 6.39045},
                                   {0.780121, -0.0186188, 6.37318},
                                   {0.737177, -0.00912791, 6.39292}};

// |U ē| for a rest edge ē given in 3D (U acts on rest-frame coordinates).
double stretchedLength(const kinematics::TriangleStrain& s, const Eigen::Vector3d& restEdge) {
  return (s.U * (s.restFrame.axes.transpose() * restEdge)).norm();
}

}  // namespace

TEST(TriangleDeformationGradient, SeedTriangleStretchGivesDeformedEdgeLengths) {
  const auto s = triangleDeformationGradient(kVertR[0], kVertR[1], kVertR[2], kVertT[0], kVertT[1], kVertT[2]);
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3;
    SCOPED_TRACE("edge " + std::to_string(i) + "-" + std::to_string(j));
    const double deformed = (kVertT[j] - kVertT[i]).norm();
    EXPECT_NEAR(stretchedLength(s, kVertR[j] - kVertR[i]), deformed, 1e-12 * deformed);
  }
  EXPECT_LT((s.U - s.U.transpose()).norm(), 1e-15);
  EXPECT_LT((s.U * s.U - s.F.transpose() * s.F).norm(), 1e-13);
  EXPECT_GE(s.principalStretches[0], s.principalStretches[1]);
  EXPECT_GT(s.principalStretches[1], 0.0);
}

// The log drops the z coordinate before forming F (eq. 13). The seed triangle's normal is
// (0.20, 0.95, -0.24), far from the z axis, so that F gets the first edge's deformed length wrong by
// more than half; this test pins the mistake down so nobody "simplifies" back to it.
TEST(TriangleDeformationGradient, DroppingACoordinateAsTheLogDoesIsWrong) {
  Eigen::Matrix2d restXY, deformedXY;
  restXY << (kVertR[1] - kVertR[0]).head<2>(), (kVertR[2] - kVertR[0]).head<2>();
  deformedXY << (kVertT[1] - kVertT[0]).head<2>(), (kVertT[2] - kVertT[0]).head<2>();
  const Eigen::Matrix2d F = deformedXY * restXY.inverse();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(F.transpose() * F);
  const Eigen::Matrix2d U = eig.eigenvectors() * eig.eigenvalues().cwiseSqrt().asDiagonal() *
                            eig.eigenvectors().transpose();
  const double logLength = (U * (kVertR[1] - kVertR[0]).head<2>()).norm();
  const double trueLength = (kVertT[1] - kVertT[0]).norm();
  EXPECT_GT(std::abs(logLength - trueLength), 0.5 * trueLength);
}

TEST(TriangleDeformationGradient, RotatingEitherTriangleDoesNotChangeU) {
  const auto reference =
      triangleDeformationGradient(kVertR[0], kVertR[1], kVertR[2], kVertT[0], kVertT[1], kVertT[2]);
  for (unsigned seed = 1; seed <= 5; ++seed) {
    const Eigen::Matrix3d Q = randomRotation(seed);
    const Eigen::Vector3d shift = Eigen::Vector3d::Random();
    Eigen::Vector3d rotatedR[3], rotatedT[3];
    for (int i = 0; i < 3; ++i) {
      rotatedR[i] = Q * kVertR[i] + shift;
      rotatedT[i] = Q.transpose() * kVertT[i] - shift;
    }
    const auto restRotated =
        triangleDeformationGradient(rotatedR[0], rotatedR[1], rotatedR[2], kVertT[0], kVertT[1], kVertT[2]);
    const auto deformedRotated =
        triangleDeformationGradient(kVertR[0], kVertR[1], kVertR[2], rotatedT[0], rotatedT[1], rotatedT[2]);
    EXPECT_LT((restRotated.U - reference.U).norm(), 1e-12);
    EXPECT_LT((deformedRotated.U - reference.U).norm(), 1e-12);
    EXPECT_LT((deformedRotated.F - reference.F).norm(), 1e-12);  // F lives in the triangles' own frames
  }
}

// A triangle in a tilted plane stretched by a along one in-plane direction and b across it.
TEST(TriangleDeformationGradient, KnownStretchOfTiltedTriangle) {
  const Eigen::Matrix3d P = randomRotation(9);
  const Eigen::Vector3d X[3] = {P * Eigen::Vector3d(0, 0, 0), P * Eigen::Vector3d(1.0, 0.2, 0),
                                P * Eigen::Vector3d(0.3, 0.8, 0)};
  const Eigen::Matrix3d A = randomRotation(10) * Eigen::Vector3d(2.5, 0.4, 1.0).asDiagonal() * P.transpose();
  const auto s = triangleDeformationGradient(X[0], X[1], X[2], A * X[0], A * X[1], A * X[2]);
  EXPECT_NEAR(s.principalStretches[0], 2.5, 1e-12);
  EXPECT_NEAR(s.principalStretches[1], 0.4, 1e-12);
  // the principal direction of the larger stretch is P's first axis (up to sign)
  const Eigen::Vector3d direction = s.restFrame.axes * s.principalDirections.col(0);
  EXPECT_NEAR(std::abs(direction.dot(P.col(0))), 1.0, 1e-12);
  EXPECT_NEAR(s.restFrame.normal.dot(P.col(2)), 1.0, 1e-12);
}

TEST(TriangleDeformationGradient, CollapsedDeformedTriangleGivesZeroStretchNotNaN) {
  const Eigen::Vector3d X0(0, 0, 0), X1(1, 0, 0), X2(0, 1, 0);
  const auto line = triangleDeformationGradient(X0, X1, X2, X0, Eigen::Vector3d(2, 0, 0), Eigen::Vector3d(1, 0, 0));
  EXPECT_TRUE(line.U.allFinite() && line.F.allFinite());
  EXPECT_NEAR(line.principalStretches[1], 0.0, 1e-12);
  EXPECT_NEAR(stretchedLength(line, X1 - X0), 2.0, 1e-12);
  EXPECT_NEAR(stretchedLength(line, X2 - X0), 1.0, 1e-12);
  const auto point = triangleDeformationGradient(X0, X1, X2, X0, X0, X0);
  EXPECT_TRUE(point.U.allFinite());
  EXPECT_EQ(point.principalStretches, Eigen::Vector2d::Zero());
}

TEST(TriangleDeformationGradient, BadInputThrows) {
  const Eigen::Vector3d X0(0, 0, 0), X1(1, 0, 0), X2(0, 1, 0);
  EXPECT_THROW(triangleDeformationGradient(X0, X1, 2.0 * X1, X0, X1, X2), InvalidInputError);
  EXPECT_THROW(triangleDeformationGradient(X0, X0, X0, X0, X1, X2), InvalidInputError);
  const Eigen::Vector3d nan = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
  EXPECT_THROW(triangleDeformationGradient(nan, X1, X2, X0, X1, X2), InvalidInputError);
  EXPECT_THROW(triangleDeformationGradient(X0, X1, X2, X0, nan, X2), InvalidInputError);
}

TEST(TriangleDeformationGradient, WholeMeshStretches) {
  // 4 x 4 grid of quads split into triangles in the plane z = 0, tilted, then deformed by an affine map
  mesh::TriangleMesh rest;
  const int n = 5;
  rest.vertices.resize(3, n * n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) rest.vertices.col(j * n + i) = Eigen::Vector3d(0.1 * i, 0.1 * j, 0.0);
  rest.triangles.resize(3, 2 * (n - 1) * (n - 1));
  int t = 0;
  for (int j = 0; j + 1 < n; ++j) {
    for (int i = 0; i + 1 < n; ++i) {
      const int v = j * n + i;
      rest.triangles.col(t++) = Eigen::Vector3i(v, v + 1, v + n + 1);
      rest.triangles.col(t++) = Eigen::Vector3i(v, v + n + 1, v + n);
    }
  }
  const Eigen::Matrix3d P = randomRotation(21);
  rest.vertices = P * rest.vertices;
  mesh::TriangleMesh deformed = rest;
  deformed.vertices = randomRotation(22) * Eigen::Vector3d(1.5, 0.8, 3.0).asDiagonal() * P.transpose() * rest.vertices;
  const Eigen::Matrix2Xd stretches = kinematics::principalStretches(rest, deformed);
  ASSERT_EQ(stretches.cols(), rest.numTriangles());
  for (Eigen::Index k = 0; k < stretches.cols(); ++k) {
    EXPECT_NEAR(stretches(0, k), 1.5, 1e-12);
    EXPECT_NEAR(stretches(1, k), 0.8, 1e-12);
  }
  // mismatches and bad positions
  mesh::TriangleMesh fewer = deformed;
  fewer.vertices.conservativeResize(3, n * n - 1);
  EXPECT_THROW(kinematics::principalStretches(rest, fewer), InvalidInputError);
  mesh::TriangleMesh other = deformed;
  other.triangles.col(0) = Eigen::Vector3i(0, 1, 2);
  EXPECT_THROW(kinematics::principalStretches(rest, other), InvalidInputError);
  mesh::TriangleMesh nan = deformed;
  nan.vertices(0, 3) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(kinematics::principalStretches(rest, nan), InvalidInputError);
  mesh::TriangleMesh degenerateRest = rest;
  degenerateRest.vertices.col(n + 1) = degenerateRest.vertices.col(0);
  EXPECT_THROW(kinematics::principalStretches(degenerateRest, deformed), InvalidInputError);
}
