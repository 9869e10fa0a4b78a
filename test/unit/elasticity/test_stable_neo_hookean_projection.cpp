// Analytic SNH eigensystem and PSD projection against a numerical 9x9 eigen-decomposition-and-clamp
// of the exact Hessian ([Smith18 §4]; docs/design.md §4).
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <Eigen/LU>
#include <cmath>
#include <random>
#include <vector>

#include "deformation_enrichment/elasticity/stable_neo_hookean.hpp"
#include "snh_variants.hpp"

using namespace deformation_enrichment::elasticity;

namespace {

Matrix9d numericalClamp(const Matrix9d& H) {
  const Eigen::SelfAdjointEigenSolver<Matrix9d> eig(H);
  const Vector9d clamped = eig.eigenvalues().cwiseMax(0.0);
  return eig.eigenvectors() * clamped.asDiagonal() * eig.eigenvectors().transpose();
}

std::vector<Eigen::Matrix3d> mixedGradients(int count, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> entry(-2.0, 2.0);
  std::normal_distribution<double> noise(0.0, 0.3);
  std::vector<Eigen::Matrix3d> out;
  for (int n = 0; n < count; ++n) {
    Eigen::Matrix3d F;
    if (n % 2 == 0) {
      for (int e = 0; e < 9; ++e) F.data()[e] = entry(rng);  // arbitrary, half of them inverted
    } else {
      F = Eigen::Matrix3d::Identity();
      for (int e = 0; e < 9; ++e) F.data()[e] += noise(rng);  // near rest
    }
    out.push_back(F);
  }
  return out;
}

// Degenerate and extreme states the simulator meets when elements are crushed, flipped or stretched.
std::vector<Eigen::Matrix3d> degenerateGradients() {
  std::vector<Eigen::Matrix3d> out;
  out.push_back(Eigen::Matrix3d::Zero());
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  out.push_back(R * Eigen::Vector3d(1.3, 0.0, 0.0).asDiagonal());                        // rank 1
  out.push_back(Eigen::Vector3d(0.5, 2.0, 0.0).asDiagonal() * R);                        // rank 2
  out.push_back(Eigen::Vector3d(1.0, 0.0, 0.0).asDiagonal().toDenseMatrix());            // rank 1, repeated 0
  out.push_back(Eigen::Vector3d(1.0, 1.0, -1.0).asDiagonal().toDenseMatrix());           // reflection
  out.push_back(-Eigen::Matrix3d::Identity());                                           // point reflection
  out.push_back(R * Eigen::Vector3d(-1.0, 1.0, 1.0).asDiagonal() * R.transpose());      // rotated reflection
  out.push_back(Eigen::Vector3d(0.6, 0.6, 0.6).asDiagonal().toDenseMatrix());            // triple sigma
  out.push_back(R * Eigen::Vector3d(1e3, 1.0, 1.0).asDiagonal());                        // huge stretch
  out.push_back(R * Eigen::Vector3d(1e6, 1e6, 1e-6).asDiagonal() * R.transpose());      // huge, flat
  out.push_back(Eigen::Vector3d(1e-9, 1e-9, -1e-9).asDiagonal().toDenseMatrix());       // crushed to a point
  out.push_back(Eigen::Vector3d(1e25, 1.0, -1e-25).asDiagonal().toDenseMatrix());      // extreme, inverted
  out.push_back(R * Eigen::Vector3d(1e-200, 0.0, 0.0).asDiagonal());                     // underflow range
  out.push_back(Eigen::Matrix3d::Identity());
  return out;
}

}  // namespace

TEST(SnhEigensystem, ReconstructsExactHessianWithOrthonormalModes) {
  for (SnhVariant variant : kSnhVariants) {
    const StableNeoHookean snh(1.1, 9.0, variant);
    for (const Eigen::Matrix3d& F : mixedGradients(200, 21)) {
      const SnhEigensystem es = snh.eigensystem(F);
      const Matrix9d H = snh.hessian(F);
      const Matrix9d rebuilt = es.vectors * es.values.asDiagonal() * es.vectors.transpose();
      EXPECT_LT((rebuilt - H).norm(), 1e-12 * H.norm());
      EXPECT_LT((es.vectors.transpose() * es.vectors - Matrix9d::Identity()).norm(), 1e-13);
    }
  }
}

TEST(SnhProjection, EqualsNumericalEigenClampOfExactHessian) {
  for (SnhVariant variant : kSnhVariants) {
    for (double lambda : {0.5, 9.0, 1e3}) {
      const StableNeoHookean snh(1.1, lambda, variant);
      int indefinite = 0;
      for (const Eigen::Matrix3d& F : mixedGradients(500, 22)) {
        const Matrix9d H = snh.hessian(F);
        const Matrix9d reference = numericalClamp(H);
        const Matrix9d projected = snh.projectedHessian(F);
        EXPECT_LE((projected - reference).norm(), 1e-10 * H.norm()) << "F=\n" << F;
        if ((projected - H).norm() > 1e-8 * H.norm()) ++indefinite;
      }
      // The sample must exercise the clamping, not only PSD states.
      EXPECT_GT(indefinite, 100);
    }
  }
}

TEST(SnhProjection, IsSymmetricPositiveSemiDefinite) {
  for (SnhVariant variant : kSnhVariants) {
    const StableNeoHookean snh(2.0, 30.0, variant);
    for (const Eigen::Matrix3d& F : mixedGradients(300, 23)) {
      const Matrix9d P = snh.projectedHessian(F);
      EXPECT_LT((P - P.transpose()).norm(), 1e-13 * P.norm());
      const double minEig = Eigen::SelfAdjointEigenSolver<Matrix9d>(P, Eigen::EigenvaluesOnly).eigenvalues()(0);
      EXPECT_GE(minEig, -1e-12 * P.norm());
    }
  }
}

TEST(SnhProjection, DegenerateAndExtremeStatesAreFinitePsdAndExact) {
  for (SnhVariant variant : kSnhVariants) {
    const StableNeoHookean snh(1.0, 10.0, variant);
    for (const Eigen::Matrix3d& F : degenerateGradients()) {
      EXPECT_TRUE(std::isfinite(snh.psi(F)));
      EXPECT_TRUE(snh.pk1(F).allFinite());
      const Matrix9d H = snh.hessian(F);
      const Matrix9d P = snh.projectedHessian(F);
      ASSERT_TRUE(H.allFinite()) << "F=\n" << F;
      ASSERT_TRUE(P.allFinite()) << "F=\n" << F;
      const SnhEigensystem es = snh.eigensystem(F);
      ASSERT_TRUE(es.values.allFinite() && es.vectors.allFinite());
      EXPECT_LE((P - numericalClamp(H)).stableNorm(), 1e-10 * H.stableNorm()) << "F=\n" << F;
      const double minEig = Eigen::SelfAdjointEigenSolver<Matrix9d>(P, Eigen::EigenvaluesOnly).eigenvalues()(0);
      EXPECT_GE(minEig, -1e-12 * P.stableNorm()) << "F=\n" << F;
    }
  }
}

TEST(SnhProjection, HugeRotatedStatesStayPsd) {
  // F = R diag(1e25, 1, -1e-25) R^T: rounding F to doubles already changes its small singular values by
  // ~1e9, and the cofactor evaluated from F cancels to O(1) relative error, so the exact Hessian from F is
  // no usable reference here. The projection is built from the eigensystem alone and must stay PSD.
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  for (SnhVariant variant : kSnhVariants) {
    const StableNeoHookean snh(1.0, 10.0, variant);
    for (double big : {1e8, 1e15, 1e25}) {
      const Eigen::Matrix3d F = R * Eigen::Vector3d(big, 1.0, -1.0 / big).asDiagonal() * R.transpose();
      const Matrix9d P = snh.projectedHessian(F);
      ASSERT_TRUE(P.allFinite());
      EXPECT_LT((P - P.transpose()).norm(), 1e-14 * P.norm());
      const double minEig = Eigen::SelfAdjointEigenSolver<Matrix9d>(P, Eigen::EigenvaluesOnly).eigenvalues()(0);
      EXPECT_GE(minEig, -1e-12 * P.norm()) << "stretch " << big;
    }
  }
}

TEST(SnhProjection, StructuredStatesWithRepeatedSingularValues) {
  // Uniform and axisymmetric scalings (and their reflections) give repeated singular values and repeated
  // scaling-block eigenvalues, including ones that cross zero as the scale factor sweeps through.
  for (SnhVariant variant : kSnhVariants) {
    const StableNeoHookean snh(1.0, 4.0, variant);
    const Eigen::Matrix3d R = Eigen::AngleAxisd(0.5, Eigen::Vector3d(1, 3, -2).normalized()).toRotationMatrix();
    for (double a = -1.5; a <= 1.5; a += 0.01) {
      for (const Eigen::Vector3d& sigma : {Eigen::Vector3d(a, a, a), Eigen::Vector3d(a, a, 1.0), Eigen::Vector3d(1.0, 1.0, a),
                                           Eigen::Vector3d(a, a, 0.0)}) {
        const Eigen::Matrix3d F = R * sigma.asDiagonal() * R.transpose();
        const Matrix9d H = snh.hessian(F);
        EXPECT_LE((snh.projectedHessian(F) - numericalClamp(H)).norm(), 1e-10 * H.norm())
            << "sigma " << sigma.transpose();
      }
    }
  }
}

TEST(SnhProjection, RandomScalesSweepStaysFiniteAndExact) {
  // Entries of random sign and magnitude 1e-6..1e6 (graded, nearly singular and huge elements).
  std::mt19937 rng(24);
  std::uniform_real_distribution<double> exponent(-6.0, 6.0);
  std::bernoulli_distribution negative(0.5);
  for (SnhVariant variant : kSnhVariants) {
    const StableNeoHookean snh(1.0, 100.0, variant);
    for (int n = 0; n < 1000; ++n) {
      Eigen::Matrix3d F;
      for (int e = 0; e < 9; ++e) F.data()[e] = (negative(rng) ? -1.0 : 1.0) * std::pow(10.0, exponent(rng));
      if (n % 2 == 1) F.col(n % 3) *= 1e-6;  // nearly flat element
      const Matrix9d H = snh.hessian(F);
      const Matrix9d P = snh.projectedHessian(F);
      ASSERT_TRUE(P.allFinite()) << "F=\n" << F;
      EXPECT_LE((P - numericalClamp(H)).norm(), 1e-10 * H.norm()) << "F=\n" << F;
    }
  }
}

TEST(SnhProjection, RestAndPositiveStatesAreNotModified) {
  // Near rest the Hessian is positive definite, so the projection must return it unchanged.
  const StableNeoHookean snh(1.0, 10.0);
  for (double t : {0.0, 1e-3, 0.05}) {
    Eigen::Matrix3d F = Eigen::Matrix3d::Identity();
    F(0, 1) = t;
    F(2, 2) += t;
    const Matrix9d H = snh.hessian(F);
    EXPECT_LT((snh.projectedHessian(F) - H).norm(), 1e-14 * H.norm());
  }
}
