// Stable Neo-Hookean energy: derivatives against finite differences, rest stability, linear-elasticity
// limit, parameter validation ([Masanti19 eq. 3.1]; docs/design.md §4).
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "deformation_enrichment/elasticity/stable_neo_hookean.hpp"
#include "deformation_enrichment/error.hpp"
#include "snh_variants.hpp"

using namespace deformation_enrichment;
using namespace deformation_enrichment::elasticity;

namespace {

// Random F around the identity; every third one is inverted by negating a column.
std::vector<Eigen::Matrix3d> randomGradients(int count, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, 0.4);
  std::vector<Eigen::Matrix3d> out;
  for (int n = 0; n < count; ++n) {
    Eigen::Matrix3d F = Eigen::Matrix3d::Identity();
    for (int e = 0; e < 9; ++e) F.data()[e] += noise(rng);
    if (n % 3 == 2) F.col(n % 3) *= -1.0;
    out.push_back(F);
  }
  return out;
}

// Linear elasticity on vec(F): d^2/dF^2 of mu |sym(F - I)|^2 + lambda/2 tr(F - I)^2 = mu (I + K) + lambda vec(I) vec(I)^T.
Matrix9d linearElasticityTensor(double mu, double lambda) {
  Matrix9d C = mu * Matrix9d::Identity();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) C(r + 3 * c, c + 3 * r) += mu;  // commutation matrix K
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) C(4 * i, 4 * j) += lambda;
  return C;
}

}  // namespace

TEST(StableNeoHookean, Pk1MatchesCentralDifferencesOfPsi) {
  for (SnhVariant variant : kSnhVariants) {
    const StableNeoHookean snh(1.3, 7.1, variant);
    for (const Eigen::Matrix3d& F : randomGradients(60, 11)) {
      const Eigen::Matrix3d P = snh.pk1(F);
      const double h = 1e-6;
      Eigen::Matrix3d fd;
      for (int e = 0; e < 9; ++e) {
        Eigen::Matrix3d Fp = F, Fm = F;
        Fp.data()[e] += h;
        Fm.data()[e] -= h;
        fd.data()[e] = (snh.psi(Fp) - snh.psi(Fm)) / (2.0 * h);
      }
      EXPECT_LT((P - fd).norm(), 1e-6 * (1.0 + P.norm())) << "F=\n" << F;
    }
  }
}

TEST(StableNeoHookean, HessianMatchesCentralDifferencesOfPk1) {
  for (SnhVariant variant : kSnhVariants) {
    const StableNeoHookean snh(0.7, 3.0, variant);
    for (const Eigen::Matrix3d& F : randomGradients(60, 12)) {
      const Matrix9d H = snh.hessian(F);
      const double h = 1e-6;
      Matrix9d fd;
      for (int e = 0; e < 9; ++e) {
        Eigen::Matrix3d Fp = F, Fm = F;
        Fp.data()[e] += h;
        Fm.data()[e] -= h;
        const Eigen::Matrix3d dP = (snh.pk1(Fp) - snh.pk1(Fm)) / (2.0 * h);
        fd.col(e) = Eigen::Map<const Vector9d>(dP.data());
      }
      EXPECT_LT((H - fd).norm(), 1e-6 * (1.0 + H.norm())) << "F=\n" << F;
      EXPECT_LT((H - H.transpose()).norm(), 1e-14 * H.norm());
    }
  }
}

TEST(StableNeoHookean, RestStateIsExactlyStressFree) {
  for (SnhVariant variant : kSnhVariants) {
    for (double mu : {1e-3, 0.37, 1.0, 2.5e4}) {
      for (double lambda : {1e-2, 1.0, 10.0, 3.3e6}) {
        const StableNeoHookean snh(mu, lambda, variant);
        const Eigen::Matrix3d P = snh.pk1(Eigen::Matrix3d::Identity());
        EXPECT_TRUE((P.array() == 0.0).all()) << "P(I) =\n" << P;
        EXPECT_EQ(snh.psi(Eigen::Matrix3d::Identity()), 0.0);
      }
    }
  }
}

TEST(StableNeoHookean, RestHessianIsLinearElasticityTensorOfUserLame) {
  for (SnhVariant variant : kSnhVariants) {
    for (double mu : {0.37, 1.0, 2.5e4}) {
      for (double lambda : {1.0, 10.0, 3.3e6}) {
        const StableNeoHookean snh(mu, lambda, variant);
        const Matrix9d C = linearElasticityTensor(mu, lambda);
        const Matrix9d H = snh.hessian(Eigen::Matrix3d::Identity());
        EXPECT_LT((H - C).norm(), 1e-12 * C.norm()) << "mu " << mu << " lambda " << lambda;
      }
    }
  }
}

TEST(StableNeoHookean, ReparametrisedConstantsFollowDesign) {
  const StableNeoHookean paper(1.2, 5.0, SnhVariant::Paper);
  EXPECT_DOUBLE_EQ(paper.muPrime(), 1.6);
  EXPECT_DOUBLE_EQ(paper.lambdaPrime(), 6.0);
  EXPECT_DOUBLE_EQ(paper.alpha(), 1.0 + 1.6 / 6.0 - 1.6 / (4.0 * 6.0));
  EXPECT_DOUBLE_EQ(paper.mu(), 1.2);
  EXPECT_DOUBLE_EQ(paper.lambda(), 5.0);
  const StableNeoHookean production(1.2, 5.0, SnhVariant::Production);
  EXPECT_DOUBLE_EQ(production.muPrime(), 1.2);
  EXPECT_DOUBLE_EQ(production.lambdaPrime(), 6.2);
  EXPECT_DOUBLE_EQ(production.alpha(), 1.0 + 1.2 / 6.2);
}

TEST(StableNeoHookean, PsiIsEquation14UpToItsRestValue) {
  // Literal eq. 3.1 / 14 with alpha from the reparametrised constants, minus its value at I.
  const double mu = 0.9, lambda = 4.0;
  const StableNeoHookean snh(mu, lambda, SnhVariant::Paper);
  const double mp = snh.muPrime(), lp = snh.lambdaPrime(), alpha = snh.alpha();
  auto literal = [&](const Eigen::Matrix3d& F) {
    const double Ic = F.squaredNorm(), J = F.determinant();
    return mp / 2 * (Ic - 3) + lp / 2 * (J - alpha) * (J - alpha) - mp / 2 * std::log(Ic + 1);
  };
  for (const Eigen::Matrix3d& F : randomGradients(20, 13)) {
    const double expected = literal(F) - literal(Eigen::Matrix3d::Identity());
    EXPECT_NEAR(snh.psi(F), expected, 1e-12 * (1.0 + std::abs(expected)));
  }
}

TEST(StableNeoHookean, InvertedStatesHaveFiniteEnergyAndRestoringStress) {
  // Stable NH has no log(J) barrier: F = 0 and reflections are finite and pushed back towards J > 0.
  for (SnhVariant variant : kSnhVariants) {
    const StableNeoHookean snh(1.0, 10.0, variant);
    const Eigen::Matrix3d reflection = Eigen::Vector3d(1.0, 1.0, -1.0).asDiagonal();
    EXPECT_TRUE(std::isfinite(snh.psi(Eigen::Matrix3d::Zero())));
    EXPECT_GT(snh.psi(reflection), snh.psi(Eigen::Matrix3d::Identity()));
    // Moving from the reflection towards the identity (raising F_22) lowers the energy.
    EXPECT_LT(snh.pk1(reflection)(2, 2), 0.0);
  }
}

TEST(StableNeoHookean, RejectsBadParametersAndInputs) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_THROW(StableNeoHookean(0.0, 1.0), InvalidInputError);
  EXPECT_THROW(StableNeoHookean(-1.0, 1.0), InvalidInputError);
  EXPECT_THROW(StableNeoHookean(1.0, 0.0), InvalidInputError);
  EXPECT_THROW(StableNeoHookean(nan, 1.0), InvalidInputError);
  EXPECT_THROW(StableNeoHookean(1.0, inf, SnhVariant::Production), InvalidInputError);
  const StableNeoHookean snh(1.0, 1.0);
  Eigen::Matrix3d F = Eigen::Matrix3d::Identity();
  F(1, 2) = nan;
  EXPECT_THROW(snh.psi(F), InvalidInputError);
  EXPECT_THROW(snh.pk1(F), InvalidInputError);
  EXPECT_THROW(snh.hessian(F), InvalidInputError);
  EXPECT_THROW(snh.projectedHessian(F), InvalidInputError);
  EXPECT_THROW(snh.eigensystem(F), InvalidInputError);
  F(1, 2) = 1e40;
  EXPECT_THROW(snh.projectedHessian(F), InvalidInputError);
}

TEST(LameParameters, YoungPoissonRoundTrip) {
  const LameParameters lame = lameFromYoungPoisson(3000.0, 0.45);
  EXPECT_NEAR(lame.mu, 3000.0 / 2.9, 1e-9);
  EXPECT_NEAR(lame.lambda, 3000.0 * 0.45 / (1.45 * 0.1), 1e-7);
  double E = 0.0, nu = 0.0;
  youngPoissonFromLame(lame, E, nu);
  EXPECT_NEAR(E, 3000.0, 1e-9);
  EXPECT_NEAR(nu, 0.45, 1e-14);
  EXPECT_THROW(lameFromYoungPoisson(-1.0, 0.3), InvalidInputError);
  EXPECT_THROW(lameFromYoungPoisson(1.0, 0.5), InvalidInputError);
  EXPECT_THROW(lameFromYoungPoisson(1.0, std::numeric_limits<double>::quiet_NaN()), InvalidInputError);
  EXPECT_THROW(youngPoissonFromLame({1.0, -1.0}, E, nu), InvalidInputError);
}
