// Closed-form symmetric 3x3 eigensolver against Eigen's iterative SelfAdjointEigenSolver, with repeated,
// nearly repeated, graded and extreme-scale spectra.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <random>

#include "deformation_enrichment/elasticity/symmetric_eigen3.hpp"

using namespace deformation_enrichment::elasticity;

TEST(SymmetricEigen3, MatchesEigenSelfAdjointSolverAndIsAccurate) {
  std::mt19937 rng(6);
  std::uniform_real_distribution<double> entry(-1.0, 1.0);
  for (int n = 0; n < 2000; ++n) {
    Eigen::Matrix3d M;
    for (int e = 0; e < 9; ++e) M.data()[e] = entry(rng);
    Eigen::Matrix3d A = M + M.transpose();
    if (n % 4 == 1) A = M * M.transpose();                            // PSD, possibly near-singular
    if (n % 4 == 2) A = Eigen::Vector3d(1.0, 1.0, entry(rng)).asDiagonal();  // repeated eigenvalues
    if (n % 4 == 3) A(0, 0) *= 1e8;                                   // strongly graded
    const SymmetricEigen3 eig = symmetricEigen3(A);
    const Eigen::Vector3d reference = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(A).eigenvalues();
    EXPECT_LT((eig.values - reference).norm(), 1e-14 * A.norm()) << "A=\n" << A;
    EXPECT_LT((A * eig.vectors - eig.vectors * eig.values.asDiagonal()).norm(), 1e-14 * A.norm());
    EXPECT_LT((eig.vectors.transpose() * eig.vectors - Eigen::Matrix3d::Identity()).norm(), 1e-14);
    EXPECT_NEAR(eig.vectors.determinant(), 1.0, 1e-14);
    EXPECT_LE(eig.values(0), eig.values(1));
    EXPECT_LE(eig.values(1), eig.values(2));
  }
  // (Near-)repeated eigenvalues, in every position, rotated: the pair must keep full accuracy.
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.9, Eigen::Vector3d(2, -1, 1).normalized()).toRotationMatrix();
  for (double gap : {0.0, 1e-15, 1e-9, 1e-4}) {
    for (const Eigen::Vector3d& lambda : {Eigen::Vector3d(1.0, 1.0 + gap, 5.0), Eigen::Vector3d(-3.0, 2.0, 2.0 + gap),
                                          Eigen::Vector3d(-1.0 - gap, -1.0, 0.0), Eigen::Vector3d(7.0, 7.0, 7.0 + gap)}) {
      const Eigen::Matrix3d A = R * lambda.asDiagonal() * R.transpose();
      const SymmetricEigen3 eig = symmetricEigen3(A);
      EXPECT_LT((eig.values - lambda).norm(), 1e-14 * lambda.norm()) << lambda.transpose();
      EXPECT_LT((A * eig.vectors - eig.vectors * eig.values.asDiagonal()).norm(), 1e-14 * A.norm());
      EXPECT_LT((eig.vectors.transpose() * eig.vectors - Eigen::Matrix3d::Identity()).norm(), 1e-14);
    }
  }
  // Entries near overflow and underflow are rescaled internally.
  for (double scale : {1e-250, 1e250}) {
    const Eigen::Matrix3d A = scale * Eigen::Matrix3d(Eigen::Vector3d(-2.0, 1.0, 3.0).asDiagonal());
    const Eigen::Matrix3d Q = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 0, 1).normalized()).toRotationMatrix();
    const SymmetricEigen3 eig = symmetricEigen3(Q * A * Q.transpose());
    EXPECT_LT((eig.values / scale - Eigen::Vector3d(-2.0, 1.0, 3.0)).norm(), 1e-14);
  }
  const SymmetricEigen3 zero = symmetricEigen3(Eigen::Matrix3d::Zero());
  EXPECT_TRUE(zero.values.isZero(0.0));
  EXPECT_TRUE(zero.vectors.isIdentity(0.0));
}


// The PSD projection against Eigen's solver with the negative eigenvalues clamped: every sign pattern of
// the spectrum, graded spectra where the pair's product cancels in the invariants (one eigenvalue 1e9
// times the others), repeated eigenvalues, and the rescaled range.
TEST(PsdProjection3, MatchesClampedEigenSolverForEverySignPattern) {
  auto clamped = [](const Eigen::Matrix3d& A) {
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(A);
    return Eigen::Matrix3d(es.eigenvectors() * es.eigenvalues().cwiseMax(0.0).asDiagonal() *
                           es.eigenvectors().transpose());
  };
  std::mt19937 rng(61);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), exponent(-9.0, 9.0);
  int pairsOfMixedSign = 0;
  for (int n = 0; n < 4000; ++n) {
    const Eigen::Matrix3d Q = Eigen::AngleAxisd(3.0 * unit(rng), Eigen::Vector3d(unit(rng), unit(rng), unit(rng)).normalized())
                                  .toRotationMatrix();
    Eigen::Vector3d lambda(unit(rng), unit(rng), unit(rng));
    if (n % 3 == 1) lambda(n % 2) *= std::pow(10.0, exponent(rng));  // graded
    if (n % 5 == 2) lambda(1) = lambda(0);                           // repeated
    const Eigen::Matrix3d A = Q * lambda.asDiagonal() * Q.transpose();
    const Eigen::Matrix3d P = psdProjection3(A);
    EXPECT_LT((P - clamped(A)).norm(), 1e-14 * A.norm()) << "eigenvalues " << lambda.transpose();
    std::sort(lambda.data(), lambda.data() + 3);
    pairsOfMixedSign += lambda(0) < 0.0 && lambda(2) > 0.0;
  }
  EXPECT_GT(pairsOfMixedSign, 1000);
  EXPECT_TRUE(psdProjection3(-2.0 * Eigen::Matrix3d::Identity()).isZero(0.0));
  EXPECT_TRUE(psdProjection3(3.0 * Eigen::Matrix3d::Identity()).isApprox(3.0 * Eigen::Matrix3d::Identity()));
  for (double scale : {1e-250, 1e250}) {
    const Eigen::Matrix3d A = scale * Eigen::Matrix3d(Eigen::Vector3d(-2.0, 1.0, 3.0).asDiagonal());
    const Eigen::Matrix3d expected = scale * Eigen::Matrix3d(Eigen::Vector3d(0.0, 1.0, 3.0).asDiagonal());
    EXPECT_LT(((psdProjection3(A) - expected) / scale).norm(), 1e-14);
  }
}
