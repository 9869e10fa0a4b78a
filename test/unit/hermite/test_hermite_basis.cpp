#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <random>
#include <sstream>
#include <string>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/hermite/hermite_basis.hpp"
#include "deformation_enrichment/hermite/moment_list.hpp"
#include "deformation_enrichment/hermite/multi_index.hpp"
#include "deformation_enrichment/hermite/symmetric_tensor.hpp"

using namespace deformation_enrichment;
using namespace deformation_enrichment::hermite;

namespace {

std::string runOracle(const std::string& arguments) {
  const std::string command =
      std::string("/usr/bin/python3 ") + DE_SOURCE_DIR + "/test/oracle/hermite_values.py " + arguments;
  FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) return "";
  std::string output;
  char buffer[4096];
  while (fgets(buffer, sizeof buffer, pipe) != nullptr) output += buffer;
  pclose(pipe);
  return output;
}

// Trapezoid grid on [-L, L]^3: spectrally accurate for Gaussian-weighted polynomials, and independent of
// any Hermite theory (no Gauss-Hermite nodes).
struct Grid {
  double spacing;
  std::vector<double> axis;
};
Grid makeGrid(double halfWidth, int pointsPerAxis) {
  Grid grid;
  grid.spacing = 2.0 * halfWidth / (pointsPerAxis - 1);
  for (int i = 0; i < pointsPerAxis; ++i) grid.axis.push_back(-halfWidth + i * grid.spacing);
  return grid;
}

// f~(r) = sum_n tau_n . H_n(r) as a full-tensor contraction (eq. 5): every distinct component counts
// multiplicity(alpha) times.
double reconstruct(const MomentList& tau, const Eigen::Vector3d& r) {
  const Eigen::VectorXd basis = evaluateBasis(r, tau.firstOrder(), tau.lastOrder());
  return (tau.multiplicities().array() * tau.values().array() * basis.array()).sum();
}

}  // namespace

TEST(MultiIndex, LexicographicOrderAndMultiplicities) {
  const auto& second = multiIndices(2);
  ASSERT_EQ(second.size(), 6u);
  const MultiIndex expected[6] = {{2, 0, 0}, {1, 1, 0}, {1, 0, 1}, {0, 2, 0}, {0, 1, 1}, {0, 0, 2}};
  for (int k = 0; k < 6; ++k) EXPECT_EQ(second[k], expected[k]) << k;
  const auto& third = multiIndices(3);
  ASSERT_EQ(third.size(), 10u);
  EXPECT_EQ(third[4], (MultiIndex{1, 1, 1}));  // xyz
  EXPECT_EQ(third[7], (MultiIndex{0, 2, 1}));  // yyz
  for (int n = 0; n <= kMaxHermiteOrder; ++n) {
    double total = 0.0;
    for (const auto& alpha : multiIndices(n)) total += multiplicity(alpha);
    EXPECT_DOUBLE_EQ(total, std::pow(3.0, n)) << "multiplicities must count all 3^n tuples";
    EXPECT_EQ(numComponents(n), static_cast<int>(multiIndices(n).size()));
  }
  EXPECT_DOUBLE_EQ(multiplicity({1, 1, 1}), 6.0);
  EXPECT_THROW(multiIndices(5), InvalidInputError);
  EXPECT_THROW(evaluateBasis(Eigen::Vector3d::Zero(), 0, 5), InvalidInputError);
}

TEST(HermiteBasis, MatchesScipyEvalHermitenorm) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> uniform(-3.0, 3.0);
  std::vector<Eigen::Vector3d> points;
  std::ostringstream arguments;
  arguments.precision(17);
  for (int k = 0; k < 12; ++k) {
    points.emplace_back(uniform(rng), uniform(rng), uniform(rng));
    arguments << points.back().x() << ' ' << points.back().y() << ' ' << points.back().z() << ' ';
  }
  std::istringstream oracle(runOracle(arguments.str()));
  for (const Eigen::Vector3d& r : points) {
    const Eigen::VectorXd ours = evaluateBasis(r, 0, kMaxHermiteOrder);
    ASSERT_EQ(ours.size(), 35);
    for (int c = 0; c < ours.size(); ++c) {
      double reference = NAN;
      ASSERT_TRUE(oracle >> reference) << "oracle output missing (python3/scipy?)";
      EXPECT_NEAR(ours[c], reference, 1e-12 * (1.0 + std::abs(reference))) << "component " << c;
    }
  }
  // A sub-range starts at the right offset.
  const Eigen::VectorXd all = evaluateBasis(points[0], 0, 4);
  const Eigen::VectorXd upper = evaluateBasis(points[0], 2, 3);
  EXPECT_EQ(upper, all.segment(orderOffset(2), basisSize(2, 3)));
}

TEST(HermiteBasis, OrthonormalUnderGaussianWindow) {
  // multiplicity(alpha) * int omega H_alpha H_beta dV = delta_alpha_beta: the tensor basis is orthonormal
  // once each distinct component is counted with its multiplicity (eq. 4-6).
  const Grid grid = makeGrid(9.0, 73);
  const int size = basisSize(0, kMaxHermiteOrder);
  Eigen::MatrixXd gram = Eigen::MatrixXd::Zero(size, size);
  const double cell = std::pow(grid.spacing, 3);
  const Eigen::Index planeSize = static_cast<Eigen::Index>(grid.axis.size() * grid.axis.size());
  Eigen::Matrix3Xd plane(3, planeSize);
  Eigen::VectorXd weight(planeSize);
  Eigen::MatrixXd basis;
  for (double x : grid.axis) {  // one plane of grid points per block evaluation
    Eigen::Index k = 0;
    for (double y : grid.axis)
      for (double z : grid.axis) {
        plane.col(k) = Eigen::Vector3d(x, y, z);
        weight(k) = gaussianWindow(plane.col(k).squaredNorm()) * cell;
        ++k;
      }
    evaluateBasis(plane, 0, kMaxHermiteOrder, basis);
    gram.noalias() += basis.transpose() * weight.asDiagonal() * basis;
  }
  MomentList layout(0, kMaxHermiteOrder);
  const Eigen::VectorXd mult = layout.multiplicities();
  const Eigen::MatrixXd normalised = mult.asDiagonal() * gram;
  EXPECT_LT((normalised - Eigen::MatrixXd::Identity(size, size)).cwiseAbs().maxCoeff(), 1e-10);
}

TEST(HermiteBasis, DotProductEqualsIntegralOfReconstructions) {
  std::mt19937 rng(11);
  std::normal_distribution<double> normal;
  MomentList tau(0, 4), v(0, 4);
  for (Eigen::Index k = 0; k < tau.values().size(); ++k) {
    tau.values()[k] = normal(rng);
    v.values()[k] = normal(rng);
  }
  const Grid grid = makeGrid(9.0, 61);
  const double cell = std::pow(grid.spacing, 3);
  double integral = 0.0;
  for (double x : grid.axis)
    for (double y : grid.axis)
      for (double z : grid.axis) {
        const Eigen::Vector3d r(x, y, z);
        integral += cell * gaussianWindow(r.squaredNorm()) * reconstruct(tau, r) * reconstruct(v, r);
      }
  // eq. (6): <f~, g~>_H = <tau, v>
  EXPECT_NEAR(integral, inner(tau, v), 1e-9 * (1.0 + std::abs(integral)));
  // Per order, the distinct-component dot equals the explicit sum over all 3^n entries (Appendix A).
  for (int n = 0; n <= 4; ++n)
    EXPECT_NEAR(fullTensorDot(n, tau.order(n), v.order(n)),
                toFullTensor(n, tau.order(n)).dot(toFullTensor(n, v.order(n))), 1e-12);
  EXPECT_NEAR(norm(tau), std::sqrt(inner(tau, tau)), 1e-15);
  EXPECT_THROW(inner(tau, MomentList(0, 3)), InvalidInputError);
}

TEST(HermiteBasis, RodriguesFormulaByFiniteDifferences) {
  // eq. (3): (-1)^n grad^n omega = sqrt(n!) H_n omega. Equivalent recurrence, checked by central differences:
  // d/dr_i [He_alpha(r) omega(r)] = -He_{alpha + e_i}(r) omega(r), for all alpha of order <= 3.
  const Eigen::Vector3d r(0.3, -0.7, 1.1);
  const double step = 1e-5;
  auto heOmega = [](const MultiIndex& alpha, const Eigen::Vector3d& x) {
    return hermiteHe(alpha[0], x[0]) * hermiteHe(alpha[1], x[1]) * hermiteHe(alpha[2], x[2]) *
           gaussianWindow(x.squaredNorm());
  };
  for (int n = 0; n <= 3; ++n)
    for (const MultiIndex& alpha : multiIndices(n))
      for (int axis = 0; axis < 3; ++axis) {
        const Eigen::Vector3d e = Eigen::Vector3d::Unit(axis) * step;
        const double derivative = (heOmega(alpha, r + e) - heOmega(alpha, r - e)) / (2.0 * step);
        MultiIndex raised = alpha;
        ++raised[axis];
        const double expected = -heOmega(raised, r);
        EXPECT_NEAR(derivative, expected, 1e-8) << "order " << n << " axis " << axis;
        // And the stored basis value is He_alpha / sqrt(n!).
        const Eigen::VectorXd basis = evaluateBasis(r, n + 1, n + 1);
        EXPECT_NEAR(basis[componentIndex(raised)] * std::sqrt(factorial(n + 1)) * gaussianWindow(r.squaredNorm()),
                    heOmega(raised, r), 1e-14);
      }
}
