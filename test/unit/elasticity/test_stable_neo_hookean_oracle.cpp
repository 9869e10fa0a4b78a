// Stable Neo-Hookean against the independent numpy oracle test/oracle/snh_oracle.py: psi from the design's
// energy formula, PK1 and Hessian by complex-step differentiation (exact to rounding), PSD projection by
// LAPACK eigh and clamping. Nothing but the energy density is shared with the C++ derivation.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include "deformation_enrichment/elasticity/stable_neo_hookean.hpp"

using namespace deformation_enrichment::elasticity;

namespace {

struct OracleRow {
  double psi;
  Eigen::Matrix3d P;
  Matrix9d H;
  Matrix9d projected;
};

std::vector<OracleRow> runOracle(double mu, double lambda, SnhVariant variant,
                                 const std::vector<Eigen::Matrix3d>& gradients) {
  const std::string stem = ::testing::TempDir() + "snh_oracle_" + std::to_string(::getpid()) +
                           (variant == SnhVariant::Paper ? "_paper" : "_production");
  {
    std::ofstream in(stem + ".in");
    in.precision(17);
    in << mu << ' ' << lambda << ' ' << (variant == SnhVariant::Paper ? "paper" : "production") << '\n';
    for (const Eigen::Matrix3d& F : gradients) {
      for (int e = 0; e < 9; ++e) in << F.data()[e] << (e == 8 ? '\n' : ' ');
    }
  }
  const std::string command = std::string("/usr/bin/python3 ") + DE_SOURCE_DIR + "/test/oracle/snh_oracle.py " +
                              stem + ".in " + stem + ".out";
  EXPECT_EQ(std::system(command.c_str()), 0) << command;
  std::vector<OracleRow> rows;
  std::ifstream out(stem + ".out");
  std::string line;
  while (std::getline(out, line)) {
    std::istringstream values(line);
    OracleRow row;
    values >> row.psi;
    for (int e = 0; e < 9; ++e) values >> row.P.data()[e];
    for (int e = 0; e < 81; ++e) values >> row.H.data()[e];
    for (int e = 0; e < 81; ++e) values >> row.projected.data()[e];
    EXPECT_FALSE(values.fail()) << "malformed oracle line";
    rows.push_back(row);
  }
  std::remove((stem + ".in").c_str());
  std::remove((stem + ".out").c_str());
  return rows;
}

std::vector<Eigen::Matrix3d> oracleGradients() {
  std::mt19937 rng(31);
  std::uniform_real_distribution<double> entry(-1.5, 1.5);
  std::vector<Eigen::Matrix3d> out;
  for (int n = 0; n < 40; ++n) {
    Eigen::Matrix3d F;
    for (int e = 0; e < 9; ++e) F.data()[e] = entry(rng);
    out.push_back(F);
  }
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.8, Eigen::Vector3d(1, -1, 2).normalized()).toRotationMatrix();
  out.push_back(Eigen::Matrix3d::Identity());
  out.push_back(Eigen::Matrix3d::Zero());
  out.push_back(R * Eigen::Vector3d(1.0, 1.0, -1.0).asDiagonal() * R.transpose());
  out.push_back(R * Eigen::Vector3d(2.0, 0.0, 0.0).asDiagonal());
  out.push_back(R * Eigen::Vector3d(0.3, 0.3, 0.3).asDiagonal());
  out.push_back(R * Eigen::Vector3d(50.0, 1.0, 0.02).asDiagonal() * R.transpose());
  return out;
}

}  // namespace

TEST(StableNeoHookeanOracle, MatchesComplexStepNumpyOracle) {
  const std::vector<Eigen::Matrix3d> gradients = oracleGradients();
  for (SnhVariant variant : {SnhVariant::Paper, SnhVariant::Production}) {
    const double mu = 1.7, lambda = 12.0;
    const StableNeoHookean snh(mu, lambda, variant);
    const std::vector<OracleRow> rows = runOracle(mu, lambda, variant, gradients);
    ASSERT_EQ(rows.size(), gradients.size());
    for (size_t n = 0; n < rows.size(); ++n) {
      const Eigen::Matrix3d& F = gradients[n];
      const OracleRow& row = rows[n];
      const double scale = 1.0 + row.H.norm();
      EXPECT_NEAR(snh.psi(F), row.psi, 1e-12 * (1.0 + std::abs(row.psi))) << "F=\n" << F;
      EXPECT_LT((snh.pk1(F) - row.P).norm(), 1e-12 * scale) << "F=\n" << F;
      EXPECT_LT((snh.hessian(F) - row.H).norm(), 1e-12 * scale) << "F=\n" << F;
      EXPECT_LT((snh.projectedHessian(F) - row.projected).norm(), 1e-10 * scale) << "F=\n" << F;
    }
  }
}
