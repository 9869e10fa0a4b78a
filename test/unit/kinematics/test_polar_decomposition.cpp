#include <gtest/gtest.h>

#include <limits>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/kinematics/polar_decomposition.hpp"

using namespace deformation_enrichment;
using kinematics::polarDecomposition;

namespace {
void expectValidPolar(const Eigen::Matrix3d& F, const kinematics::PolarDecomposition& pd) {
  EXPECT_TRUE(pd.R.allFinite() && pd.S.allFinite());
  EXPECT_LT((pd.R * pd.S - F).norm(), 1e-12 * (1.0 + F.norm()));
  EXPECT_LT((pd.R.transpose() * pd.R - Eigen::Matrix3d::Identity()).norm(), 1e-12);
  EXPECT_NEAR(pd.R.determinant(), 1.0, 1e-12);
  EXPECT_LT((pd.S - pd.S.transpose()).norm(), 1e-15 * (1.0 + F.norm()));
}
}  // namespace

TEST(PolarDecomposition, PropertiesOnRandomAndSpecialMatrices) {
  std::srand(1);
  for (int k = 0; k < 50; ++k) {
    const Eigen::Matrix3d F = Eigen::Matrix3d::Random();
    const auto pd = polarDecomposition(F);
    expectValidPolar(F, pd);
    // det F > 0: S is the positive definite stretch; det F < 0: exactly one negative eigenvalue
    const Eigen::Vector3d eig = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(pd.S).eigenvalues();
    if (F.determinant() > 0) {
      EXPECT_GT(eig.minCoeff(), 0.0);
    } else {
      EXPECT_LT(eig[0], 0.0);
      EXPECT_GT(eig[1], 0.0);
    }
  }
  expectValidPolar(Eigen::Matrix3d::Zero(), polarDecomposition(Eigen::Matrix3d::Zero()));
  expectValidPolar(Eigen::Matrix3d::Identity(), polarDecomposition(Eigen::Matrix3d::Identity()));
  const Eigen::Matrix3d reflection = Eigen::Vector3d(1, 1, -1).asDiagonal();
  expectValidPolar(reflection, polarDecomposition(reflection));
  Eigen::Matrix3d rank1 = Eigen::Vector3d(1, 2, 3) * Eigen::RowVector3d(0.5, -1, 2);
  expectValidPolar(rank1, polarDecomposition(rank1));
}

TEST(PolarDecomposition, RotationOfStretchIsRecovered) {
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, -2, 0.5).normalized()).toRotationMatrix();
  Eigen::Matrix3d S;
  S << 1.2, 0.1, 0.0,  //
      0.1, 0.9, -0.2,  //
      0.0, -0.2, 1e-9;  // near-singular but positive definite
  const auto pd = polarDecomposition(R * S);
  EXPECT_LT((pd.R - R).norm(), 1e-9);
  EXPECT_LT((pd.S - S).norm(), 1e-12);
}

TEST(PolarDecomposition, NaNThrows) {
  Eigen::Matrix3d F = Eigen::Matrix3d::Identity();
  F(1, 2) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(polarDecomposition(F), InvalidInputError);
  F(1, 2) = std::numeric_limits<double>::infinity();
  EXPECT_THROW(polarDecomposition(F), InvalidInputError);
}
