// Finite-difference checks of every derivative of the Discrete Shells energies: gradients in both
// arguments and the three Hessian blocks, for both membranes, on an open and a closed mesh.
#include <gtest/gtest.h>

#include <functional>
#include <ostream>
#include <string>

#include "deformation_enrichment/shape_space/dihedral_angle.hpp"
#include "deformation_enrichment/shape_space/discrete_shells.hpp"
#include "shell_test_meshes.hpp"

namespace deformation_enrichment::shape_space {
namespace {

using Eigen::VectorXd;

// Central difference of a scalar function of x.
VectorXd numericGradient(const std::function<double(const VectorXd&)>& f, const VectorXd& x, double h) {
  VectorXd g(x.size());
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    VectorXd plus = x, minus = x;
    plus[i] += h;
    minus[i] -= h;
    g[i] = (f(plus) - f(minus)) / (2.0 * h);
  }
  return g;
}

// Central difference of a vector function of x: column j = d f / d x_j.
Eigen::MatrixXd numericJacobian(const std::function<VectorXd(const VectorXd&)>& f, const VectorXd& x, double h) {
  const Eigen::Index n = x.size();
  Eigen::MatrixXd jacobian(f(x).size(), n);
  for (Eigen::Index j = 0; j < n; ++j) {
    VectorXd plus = x, minus = x;
    plus[j] += h;
    minus[j] -= h;
    jacobian.col(j) = (f(plus) - f(minus)) / (2.0 * h);
  }
  return jacobian;
}

void expectClose(const Eigen::MatrixXd& analytic, const Eigen::MatrixXd& numeric, double relTol, const std::string& what) {
  ASSERT_EQ(analytic.rows(), numeric.rows()) << what;
  ASSERT_EQ(analytic.cols(), numeric.cols()) << what;
  const double scale = std::max(1.0, numeric.cwiseAbs().maxCoeff());
  const double error = (analytic - numeric).cwiseAbs().maxCoeff();
  EXPECT_LT(error, relTol * scale) << what << ": max |analytic - finite difference| = " << error << ", scale " << scale;
  EXPECT_GT(analytic.cwiseAbs().maxCoeff(), 0.0) << what << " is identically zero: the check would be vacuous";
}

struct Case {
  const char* name;
  DiscreteShellsOptions parameters;
  bool closed;
};

void PrintTo(const Case& c, std::ostream* os) { *os << c.name; }

class ShellDerivatives : public ::testing::TestWithParam<Case> {};

TEST_P(ShellDerivatives, GradientsAndAllHessianBlocksMatchFiniteDifferences) {
  const Case& c = GetParam();
  const test::FlatMesh mesh = c.closed ? test::octahedron() : test::bumpyGrid(4, 3);
  // Large bending weight so bending derivatives are not drowned by the membrane in the comparison.
  DiscreteShellsOptions parameters = c.parameters;
  parameters.bendingWeight = 0.7;
  const DiscreteShells energy(mesh.triangles, mesh.vertices.size() / 3, parameters);
  const VectorXd reference = mesh.vertices;
  const VectorXd deformed = test::perturbed(reference, 0.08, 11);
  const double h = 1e-6;

  const test::AllOutputs all = test::evaluateAll(energy, reference, deformed);
  EXPECT_NEAR(all.value, energy.value(reference, deformed), 1e-12 * std::abs(all.value));
  EXPECT_GT(energy.bendingValue(reference, deformed), 0.0);

  const VectorXd gradientDeformed = energy.gradientDeformed(reference, deformed);
  const VectorXd gradientReference = energy.gradientReference(reference, deformed);
  expectClose(gradientDeformed, all.gradientDeformed, 1e-12, "gradientDeformed vs evaluate()");
  expectClose(gradientDeformed,
              numericGradient([&](const VectorXd& x) { return energy.value(reference, x); }, deformed, h), 1e-6,
              "dW/dx");
  expectClose(gradientReference,
              numericGradient([&](const VectorXd& xBar) { return energy.value(xBar, deformed); }, reference, h), 1e-6,
              "dW/dx_bar");

  const Eigen::MatrixXd hessianDeformed = Eigen::MatrixXd(energy.hessianDeformed(reference, deformed));
  const Eigen::MatrixXd hessianMixed = Eigen::MatrixXd(energy.hessianMixed(reference, deformed));
  const Eigen::MatrixXd hessianReference = Eigen::MatrixXd(energy.hessianReference(reference, deformed));
  expectClose(hessianDeformed, hessianDeformed.transpose(), 1e-10, "d2W/dx2 symmetry");
  // Alone it is in closed form (hyperelastic); with the other blocks, by jets in the squared lengths.
  expectClose(hessianDeformed, Eigen::MatrixXd(all.hessianDeformed), 1e-10, "d2W/dx2 alone vs with all blocks");
  expectClose(hessianReference, hessianReference.transpose(), 1e-10, "d2W/dx_bar2 symmetry");
  expectClose(hessianDeformed,
              numericJacobian([&](const VectorXd& x) { return energy.gradientDeformed(reference, x); }, deformed, h),
              1e-5, "d2W/dx2");
  // Row i of the mixed block = d/dx_bar_i of dW/dx^T, i.e. the transpose of the Jacobian of dW/dx in x_bar.
  expectClose(hessianMixed,
              numericJacobian([&](const VectorXd& xBar) { return energy.gradientDeformed(xBar, deformed); }, reference, h)
                  .transpose(),
              1e-5, "d2W/dx_bar dx (via dW/dx)");
  expectClose(hessianMixed,
              numericJacobian([&](const VectorXd& x) { return energy.gradientReference(reference, x); }, deformed, h),
              1e-5, "d2W/dx_bar dx (via dW/dx_bar)");
  expectClose(hessianReference,
              numericJacobian([&](const VectorXd& xBar) { return energy.gradientReference(xBar, deformed); }, reference, h),
              1e-5, "d2W/dx_bar2");
}

INSTANTIATE_TEST_SUITE_P(
    BothMembranes, ShellDerivatives,
    ::testing::Values(Case{"hyperelastic_open", DiscreteShellsOptions::hyperelastic(), false},
                      Case{"hyperelastic_closed", DiscreteShellsOptions::hyperelastic(), true},
                      Case{"classic_open", DiscreteShellsOptions::classic(), false},
                      Case{"classic_closed", DiscreteShellsOptions::classic(), true}),
    [](const ::testing::TestParamInfo<Case>& info) { return std::string(info.param.name); });

TEST(DihedralAngle, GradientAndHessianMatchFiniteDifferences) {
  // A bent hinge, one folded past pi / 2 and a nearly flat one (the closed-form Hessian's every branch).
  for (const double lift : {0.35, -2.5, 0.01}) {
    VectorXd x(12);
    x << 0.1, -0.05, 0.02, 1.0, 0.1, -0.03, 0.4, 0.9, lift, 0.6, -0.8, 0.2;
    auto angle = [](const VectorXd& p) {
      return dihedralAngle(p.segment<3>(0), p.segment<3>(3), p.segment<3>(6), p.segment<3>(9));
    };
    auto gradient = [](const VectorXd& p) -> VectorXd {
      return dihedralAngleDerivatives(p.segment<3>(0), p.segment<3>(3), p.segment<3>(6), p.segment<3>(9), false).gradient;
    };
    const HingeAngle full = dihedralAngleDerivatives(x.segment<3>(0), x.segment<3>(3), x.segment<3>(6), x.segment<3>(9), true);
    EXPECT_NEAR(full.theta, angle(x), 1e-15);
    expectClose(full.gradient, numericGradient(angle, x, 1e-6), 1e-8, "d theta / dx");
    expectClose(full.hessian, numericJacobian(gradient, x, 1e-6), 1e-6, "d2 theta / dx2");
  }
}

TEST(DihedralAngle, SharedAngleAndGradientMatchSeparateCallsAndFiniteDifferences) {
  // A bent hinge and one folded past pi / 2 (the obtuse side of atan2).
  for (const double lift : {0.35, -2.5}) {
    VectorXd x(12);
    x << 0.1, -0.05, 0.02, 1.0, 0.1, -0.03, 0.4, 0.9, lift, 0.6, -0.8, 0.2;
    auto angle = [](const VectorXd& p) {
      return dihedralAngle(p.segment<3>(0), p.segment<3>(3), p.segment<3>(6), p.segment<3>(9));
    };
    Eigen::Matrix<double, 12, 1> gradient;
    const double theta = dihedralAngleAndGradient(x.segment<3>(0), x.segment<3>(3), x.segment<3>(6), x.segment<3>(9), gradient);
    EXPECT_NEAR(theta, angle(x), 1e-15);
    expectClose(VectorXd(gradient), VectorXd(dihedralAngleGradient(x.segment<3>(0), x.segment<3>(3), x.segment<3>(6), x.segment<3>(9))),
                1e-13, "shared vs separate gradient");
    expectClose(VectorXd(gradient), numericGradient(angle, x, 1e-6), 1e-8, "d theta / dx (shared)");
  }
}

TEST(DihedralAngle, DifferenceFromAngleVectorsIsTheWrappedDifference) {
  // Hinges folded by angles phi (wing k rotated about the edge); pairs across +-pi must wrap to a small step.
  const Eigen::Vector3d i(0, 0, 0), j(1, 0, 0), l(0.4, -1, 0);
  const auto folded = [&](double phi) { return Eigen::Vector3d(0.6, std::cos(phi), std::sin(phi)); };
  for (const double a : {0.3, 2.9, 3.1, -3.1, -1.0}) {
    for (const double b : {0.0, 3.12, -3.12, 1.5, -2.0}) {
      const Eigen::Vector3d ka = folded(a), kb = folded(b);
      const double expected = std::remainder(dihedralAngle(i, j, ka, l) - dihedralAngle(i, j, kb, l), 2.0 * M_PI);
      const double difference = dihedralAngleDifference(dihedralAngleVector(i, j, ka, l), dihedralAngleVector(i, j, kb, l));
      EXPECT_NEAR(difference, expected, 1e-13) << "a " << a << ", b " << b;
      EXPECT_LE(std::abs(difference), M_PI);
    }
    EXPECT_NEAR(std::atan2(dihedralAngleVector(i, j, folded(a), l)[0], dihedralAngleVector(i, j, folded(a), l)[1]),
                dihedralAngle(i, j, folded(a), l), 1e-14);
  }
}

TEST(DihedralAngle, FlatHingeIsZeroAndFoldingSignIsSymmetric) {
  const Eigen::Vector3d i(0, 0, 0), j(1, 0, 0), k(0.5, 1, 0), l(0.5, -1, 0);
  EXPECT_NEAR(dihedralAngle(i, j, k, l), 0.0, 1e-15);
  // Lifting either wing by the same height gives the same angle (valley fold), lowering gives the opposite.
  const Eigen::Vector3d up(0, 0, 0.3);
  EXPECT_NEAR(dihedralAngle(i, j, k + up, l), dihedralAngle(i, j, k, l + up), 1e-14);
  EXPECT_NEAR(dihedralAngle(i, j, k + up, l), -dihedralAngle(i, j, k - up, l), 1e-14);
  EXPECT_NEAR(std::abs(dihedralAngle(i, j, k + up, l)), std::atan(0.3), 1e-14);
}

}  // namespace
}  // namespace deformation_enrichment::shape_space
