// Rotation-variant SVD: reconstruction, proper rotations, reflection in the smallest singular value,
// agreement with Eigen's JacobiSVD (an independent two-sided Jacobi implementation).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <Eigen/SVD>
#include <limits>
#include <random>

#include "deformation_enrichment/elasticity/rotation_variant_svd.hpp"
#include "deformation_enrichment/error.hpp"

using namespace deformation_enrichment;
using namespace deformation_enrichment::elasticity;

namespace {
void expectValid(const Eigen::Matrix3d& F, const RotationVariantSvd& svd) {
  const double scale = std::max(1.0, F.norm());
  EXPECT_LT((svd.U * svd.sigma.asDiagonal() * svd.V.transpose() - F).norm(), 1e-13 * scale) << "F=\n" << F;
  EXPECT_NEAR(svd.U.determinant(), 1.0, 1e-13);
  EXPECT_NEAR(svd.V.determinant(), 1.0, 1e-13);
  EXPECT_LT((svd.U.transpose() * svd.U - Eigen::Matrix3d::Identity()).norm(), 1e-13);
  EXPECT_LT((svd.V.transpose() * svd.V - Eigen::Matrix3d::Identity()).norm(), 1e-13);
  // Sorted by magnitude up to rounding at ties.
  EXPECT_GE(svd.sigma(0), svd.sigma(1) - 1e-14 * scale);
  EXPECT_GE(svd.sigma(1), std::abs(svd.sigma(2)) - 1e-14 * scale);
  // Magnitudes agree with Eigen's JacobiSVD (independent two-sided Jacobi algorithm).
  const Eigen::Vector3d reference = Eigen::JacobiSVD<Eigen::Matrix3d>(F).singularValues();
  EXPECT_LT((svd.sigma.cwiseAbs() - reference).norm(), 1e-13 * scale) << "F=\n" << F;
  // The sign of det F lives in sigma_2 only.
  if (F.determinant() < -1e-12 * scale * scale * scale) {
    EXPECT_LT(svd.sigma(2), 0.0);
  }
  if (F.determinant() > 1e-12 * scale * scale * scale) {
    EXPECT_GT(svd.sigma(2), 0.0);
  }
  EXPECT_GE(svd.sigma(1), 0.0);
}
}  // namespace

TEST(RotationVariantSvd, RandomMatricesIncludingReflections) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> entry(-3.0, 3.0);
  int reflections = 0;
  for (int n = 0; n < 2000; ++n) {
    Eigen::Matrix3d F;
    for (int e = 0; e < 9; ++e) F.data()[e] = entry(rng);
    if (F.determinant() < 0.0) ++reflections;
    expectValid(F, rotationVariantSvd(F));
  }
  EXPECT_GT(reflections, 500);
}

TEST(RotationVariantSvd, DegenerateMatrices) {
  const Eigen::Matrix3d R = Eigen::AngleAxisd(1.1, Eigen::Vector3d(-1, 2, 0.5).normalized()).toRotationMatrix();
  const Eigen::Matrix3d cases[] = {
      Eigen::Matrix3d::Zero(),
      Eigen::Matrix3d::Identity(),
      -Eigen::Matrix3d::Identity(),
      Eigen::Vector3d(1.0, 1.0, -1.0).asDiagonal().toDenseMatrix(),
      R * Eigen::Vector3d(2.0, 0.0, 0.0).asDiagonal(),
      R * Eigen::Vector3d(2.0, 2.0, 0.0).asDiagonal() * R.transpose(),
      R * Eigen::Vector3d(1e8, 1.0, -1e-8).asDiagonal() * R.transpose(),
      R,
      -R,
  };
  for (const Eigen::Matrix3d& F : cases) expectValid(F, rotationVariantSvd(F));
  const RotationVariantSvd reflection = rotationVariantSvd(-Eigen::Matrix3d::Identity());
  EXPECT_NEAR(reflection.sigma(2), -1.0, 1e-15);
}

TEST(RotationVariantSvd, GradedAndExtremeScales) {
  // Small singular values keep relative accuracy (QR of A V, not sqrt of eig(A^T A)).
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, 1, 0).normalized()).toRotationMatrix();
  const Eigen::Matrix3d S = Eigen::AngleAxisd(-1.3, Eigen::Vector3d(0, 1, 2).normalized()).toRotationMatrix();
  const Eigen::Vector3d graded(1e4, 1.0, -1e-4);
  const RotationVariantSvd svd = rotationVariantSvd(R * graded.asDiagonal() * S.transpose());
  EXPECT_NEAR(svd.sigma(0), 1e4, 1e-11);
  EXPECT_NEAR(svd.sigma(1), 1.0, 1e-12);
  EXPECT_NEAR(svd.sigma(2), -1e-4, 1e-12);
  // Entries near overflow and underflow are rescaled internally.
  for (double scale : {1e-200, 1e200}) {
    const Eigen::Matrix3d F = scale * (R * Eigen::Vector3d(3.0, 2.0, -1.0).asDiagonal() * S.transpose());
    const RotationVariantSvd big = rotationVariantSvd(F);
    EXPECT_TRUE(big.sigma.allFinite() && big.U.allFinite() && big.V.allFinite());
    EXPECT_NEAR(big.sigma(0) / scale, 3.0, 1e-13);
    EXPECT_NEAR(big.sigma(2) / scale, -1.0, 1e-13);
  }
}

TEST(RotationVariantSvd, RejectsNonFinite) {
  Eigen::Matrix3d F = Eigen::Matrix3d::Identity();
  F(0, 2) = std::numeric_limits<double>::infinity();
  EXPECT_THROW(rotationVariantSvd(F), InvalidInputError);
}
