#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>

#include <Eigen/Geometry>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/kinematics/mls_deformation_gradient.hpp"
#include "deformation_enrichment/kinematics/polar_decomposition.hpp"
#include "random_rotation.hpp"

using namespace deformation_enrichment;
using kinematics::mlsDeformationGradient;

namespace {

// Gaussian weights of the samples around p, as the descriptors use them.
Eigen::VectorXd gaussianWeights(const Eigen::Matrix3Xd& x, const Eigen::Vector3d& p, double h) {
  Eigen::VectorXd w(x.cols());
  for (Eigen::Index m = 0; m < x.cols(); ++m) w[m] = std::exp(-0.5 * (x.col(m) - p).squaredNorm() / (h * h));
  return w;
}

}  // namespace

TEST(MlsDeformationGradient, ExactForAffineDeformationOf3DCloud) {
  std::srand(7);
  const Eigen::Matrix3Xd x = Eigen::Matrix3Xd::Random(3, 40);
  Eigen::Matrix3d A;
  A << 1.3, 0.2, -0.1,  //
      -0.4, 0.8, 0.3,   //
      0.1, 0.5, 1.1;
  const Eigen::Vector3d b(0.3, -2.0, 5.0);
  const Eigen::Matrix3Xd y = (A * x).colwise() + b;
  const Eigen::VectorXd w = gaussianWeights(x, Eigen::Vector3d(0.2, 0.1, 0.0), 0.5);
  const auto r = mlsDeformationGradient(x, y, w);
  EXPECT_FALSE(r.normalCompleted);
  EXPECT_LT((r.F - A).norm(), 1e-12);
  EXPECT_LT((r.xBar - x * w / w.sum()).norm(), 1e-14);
  EXPECT_LT((r.yBar - (A * r.xBar + b)).norm(), 1e-12);
}

TEST(MlsDeformationGradient, ExactForInvertingAffineDeformation) {
  std::srand(8);
  const Eigen::Matrix3Xd x = Eigen::Matrix3Xd::Random(3, 20);
  const Eigen::Matrix3d A = Eigen::Vector3d(1.0, 1.0, -0.5).asDiagonal();
  const Eigen::Matrix3Xd y = A * x;
  const auto r = mlsDeformationGradient(x, y, Eigen::VectorXd::Ones(20));
  EXPECT_LT((r.F - A).norm(), 1e-12);
}

// A flat contact patch: rest samples in a tilted plane, deformed by an affine map that stretches the
// plane and maps the rest normal to the deformed normal with the deformation-transfer stretch
// sqrt(area ratio). Then the completed F must equal that map exactly.
TEST(MlsDeformationGradient, CoplanarPatchWithNormalsIsExact) {
  const Eigen::Matrix3d P = randomRotation(3);  // columns: tangent 1, tangent 2, rest normal
  std::srand(11);
  const Eigen::Matrix2Xd uv = Eigen::Matrix2Xd::Random(2, 30);
  const Eigen::Matrix3Xd x = (P.leftCols<2>() * uv).colwise() + Eigen::Vector3d(1.0, 2.0, 3.0);
  Eigen::Matrix2d G;  // in-plane stretch and shear
  G << 1.4, 0.3,  //
      -0.2, 0.7;
  const double areaRatio = G.determinant();
  Eigen::Matrix3d local = Eigen::Matrix3d::Zero();  // in the (t1, t2, n) basis
  local.topLeftCorner<2, 2>() = G;
  local(2, 2) = std::sqrt(areaRatio);
  const Eigen::Matrix3d Q = randomRotation(5);
  // deformed frame Q: in-plane map then normal; A = Q local Pᵀ
  const Eigen::Matrix3d A = Q * local * P.transpose();
  const Eigen::Matrix3Xd y = (A * x).colwise() + Eigen::Vector3d(-1.0, 0.5, 0.0);
  const Eigen::Vector3d nx = P.col(2), ny = Q.col(2);
  const Eigen::VectorXd w = gaussianWeights(x, x.col(0), 0.7);

  EXPECT_THROW(mlsDeformationGradient(x, y, w), InvalidInputError);  // flat and no normals
  const auto r = mlsDeformationGradient(x, y, w, 2.0 * nx, 0.5 * ny);  // normals need not be unit
  EXPECT_TRUE(r.normalCompleted);
  EXPECT_LT((r.F - A).norm(), 1e-11);

  kinematics::MlsOptions unit;
  unit.normalStretch = kinematics::NormalStretch::Unit;
  EXPECT_LT((mlsDeformationGradient(x, y, w, nx, ny, unit).F * nx - ny).norm(), 1e-11);
  kinematics::MlsOptions incompressible;
  incompressible.normalStretch = kinematics::NormalStretch::VolumePreserving;
  EXPECT_NEAR(mlsDeformationGradient(x, y, w, nx, ny, incompressible).F.determinant(), 1.0, 1e-11);
}

namespace {
// Points on a spherical cap of radius radius around the north pole (rest normal +z at the pole),
// on an irregular (random) set of sample positions, so nothing cancels by symmetry.
Eigen::Matrix3Xd sphericalCap(double radius, double capRadius, int count, unsigned seed) {
  std::srand(seed);
  Eigen::Matrix3Xd x(3, count);
  for (int m = 0; m < count; ++m) {
    const Eigen::Vector2d t = capRadius * Eigen::Vector2d::Random();
    x.col(m) << t, std::sqrt(radius * radius - t.squaredNorm()) - radius;  // pole at the origin
  }
  return x;
}
}  // namespace

// Surface samples on a curved patch: a rigid motion gives F = R exactly (so descriptors built on it are
// exactly rigid-invariant), and so does an affine map with consistent normals and matching stretch.
TEST(MlsDeformationGradient, CurvedSurfacePatchRigidAndAffineAreExact) {
  const Eigen::Matrix3Xd x = sphericalCap(0.1, 0.04, 60, 12);
  const Eigen::VectorXd w = gaussianWeights(x, Eigen::Vector3d(0.005, -0.003, 0.0), 0.015);
  const Eigen::Vector3d nx = Eigen::Vector3d::UnitZ();
  const Eigen::Matrix3d Q = randomRotation(13);
  const auto rigid = mlsDeformationGradient(x, (Q * x).colwise() + Eigen::Vector3d(1, 2, 3), w, nx, Q * nx);
  EXPECT_TRUE(rigid.normalCompleted);
  EXPECT_LT((rigid.F - Q).norm(), 1e-12);

  Eigen::Matrix3d local = Eigen::Matrix3d::Zero();
  local.topLeftCorner<2, 2>() << 1.2, 0.3, -0.1, 0.9;
  local(2, 2) = std::sqrt(local.topLeftCorner<2, 2>().determinant());
  const Eigen::Matrix3d A = Q * local;
  const auto affine = mlsDeformationGradient(x, A * x, w, nx, Q * nx);
  EXPECT_LT((affine.F - A).norm(), 1e-12);
}

// Why surface samples need the normals: a 5 mm deep, 1 cm wide indentation at the pole of a 10 cm
// sphere. The plain fit reads the normal column off the curvature offsets and inverts F; the surface
// fit keeps the normal and the (absent) rotation at the indentation centre.
TEST(MlsDeformationGradient, IndentationOfCurvedSurfaceNeedsTheNormals) {
  const double radius = 0.1, depth = 0.005, width = 0.01, h = 0.01;
  const Eigen::Matrix3Xd x = sphericalCap(radius, 0.04, 2000, 14);
  Eigen::Matrix3Xd y = x;
  for (Eigen::Index m = 0; m < x.cols(); ++m) {
    const Eigen::Vector3d n = (x.col(m) + Eigen::Vector3d(0, 0, radius)).normalized();  // sphere normal
    y.col(m) -= depth * std::exp(-0.5 * x.col(m).head<2>().squaredNorm() / (width * width)) * n;
  }
  const Eigen::VectorXd w = gaussianWeights(x, Eigen::Vector3d::Zero(), h);
  const Eigen::Vector3d nz = Eigen::Vector3d::UnitZ();
  const auto plain = mlsDeformationGradient(x, y, w);
  const auto surface = mlsDeformationGradient(x, y, w, nz, nz);
  std::printf("indentation: plain fit F_zz = %.3f, det F = %.3f; surface fit F_zz = %.3f, det F = %.3f\n",
              plain.F(2, 2), plain.F.determinant(), surface.F(2, 2), surface.F.determinant());
  EXPECT_LT(plain.F.determinant(), 0.0);  // the hazard this overload exists for
  EXPECT_GT(surface.F.determinant(), 0.5);
  // no spurious rotation at the centre (the random samples are only statistically symmetric)
  EXPECT_LT((kinematics::polarDecomposition(surface.F).R - Eigen::Matrix3d::Identity()).norm(), 1e-3);
  EXPECT_NEAR(surface.F(2, 2), std::sqrt(surface.F.topLeftCorner<2, 2>().determinant()), 1e-12);
}

TEST(MlsDeformationGradient, BadInputThrowsTypedErrors) {
  std::srand(10);
  const Eigen::Matrix3Xd x = Eigen::Matrix3Xd::Random(3, 6);
  const Eigen::VectorXd w = Eigen::VectorXd::Ones(6);
  const Eigen::Vector3d n = Eigen::Vector3d::UnitZ();
  EXPECT_THROW(mlsDeformationGradient(Eigen::Matrix3Xd(3, 0), Eigen::Matrix3Xd(3, 0), Eigen::VectorXd(0)),
               InvalidInputError);
  EXPECT_THROW(mlsDeformationGradient(x, x.leftCols(5), w), InvalidInputError);
  EXPECT_THROW(mlsDeformationGradient(x, x, Eigen::VectorXd::Ones(5)), InvalidInputError);
  EXPECT_THROW(mlsDeformationGradient(x, x, Eigen::VectorXd::Zero(6)), InvalidInputError);
  Eigen::VectorXd negative = w;
  negative[2] = -1.0;
  EXPECT_THROW(mlsDeformationGradient(x, x, negative), InvalidInputError);
  Eigen::Matrix3Xd nan = x;
  nan(1, 3) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(mlsDeformationGradient(nan, x, w), InvalidInputError);
  EXPECT_THROW(mlsDeformationGradient(x, nan, w), InvalidInputError);
  Eigen::VectorXd nanW = w;
  nanW[0] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(mlsDeformationGradient(x, x, nanW), InvalidInputError);
  // coincident and collinear samples: F undefined even with normals
  const Eigen::Matrix3Xd same = Eigen::Vector3d(1, 2, 3).replicate(1, 6);
  EXPECT_THROW(mlsDeformationGradient(same, same, w, n, n), InvalidInputError);
  Eigen::Matrix3Xd line(3, 6);
  for (int m = 0; m < 6; ++m) line.col(m) = Eigen::Vector3d(1, 1, 0) * m;
  EXPECT_THROW(mlsDeformationGradient(line, line, w, n, n), InvalidInputError);
  // flat patch: zero / NaN normal, or a normal lying in the patch plane
  Eigen::Matrix3Xd flat = x;
  flat.row(2).setZero();
  EXPECT_THROW(mlsDeformationGradient(flat, flat, w, Eigen::Vector3d::Zero(), n), InvalidInputError);
  EXPECT_THROW(mlsDeformationGradient(flat, flat, w, n, Eigen::Vector3d::Constant(NAN)), InvalidInputError);
  EXPECT_THROW(mlsDeformationGradient(flat, flat, w, Eigen::Vector3d::UnitX(), n), InvalidInputError);
  EXPECT_NO_THROW(mlsDeformationGradient(flat, flat, w, n, n));
  // a single sample with non-zero weight is a coincident set
  Eigen::VectorXd one = Eigen::VectorXd::Zero(6);
  one[4] = 1.0;
  EXPECT_THROW(mlsDeformationGradient(x, x, one), InvalidInputError);
}

// F depends on relative weights only; huge or subnormal weights must neither overflow nor vanish.
TEST(MlsDeformationGradient, WeightScaleDoesNotMatter) {
  std::srand(15);
  const Eigen::Matrix3Xd x = Eigen::Matrix3Xd::Random(3, 12);
  const Eigen::Matrix3Xd y = x + 0.2 * Eigen::Matrix3Xd::Random(3, 12);
  const Eigen::VectorXd w = Eigen::VectorXd::Random(12).cwiseAbs();
  const auto reference = mlsDeformationGradient(x, y, w);
  for (double scale : {1e300, 1e-310}) {
    const auto scaled = mlsDeformationGradient(x, y, Eigen::VectorXd(scale * w));
    EXPECT_TRUE(scaled.F.allFinite());
    EXPECT_LT((scaled.F - reference.F).norm(), 1e-9);
    EXPECT_LT((scaled.yBar - reference.yBar).norm(), 1e-12);
  }
}
