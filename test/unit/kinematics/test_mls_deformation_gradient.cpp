#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include <Eigen/Geometry>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/kinematics/mls_deformation_gradient.hpp"

using namespace deformation_enrichment;
using kinematics::mlsDeformationGradient;

namespace {

Eigen::Matrix3d randomRotation(unsigned seed) {
  std::srand(seed);
  return Eigen::Quaterniond(Eigen::Vector4d::Random()).normalized().toRotationMatrix();
}

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

// Normals are only a completion: a genuinely 3D cloud ignores them (no bias of the exact fit).
TEST(MlsDeformationGradient, NormalsIgnoredFor3DCloud) {
  std::srand(9);
  const Eigen::Matrix3Xd x = Eigen::Matrix3Xd::Random(3, 15);
  const Eigen::Matrix3d A = randomRotation(4) * Eigen::Vector3d(1.2, 0.9, 1.1).asDiagonal();
  const auto r = mlsDeformationGradient(x, A * x, Eigen::VectorXd::Ones(15), Eigen::Vector3d::UnitZ(),
                                        Eigen::Vector3d::UnitX());
  EXPECT_FALSE(r.normalCompleted);
  EXPECT_LT((r.F - A).norm(), 1e-12);
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
