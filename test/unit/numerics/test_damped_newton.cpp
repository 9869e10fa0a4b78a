// The shared damped Newton minimiser: converges on stiff and non-convex problems (dense, BFGS, sparse),
// never accepts an infeasible or higher point, and reports instead of throwing when it cannot converge.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/numerics/damped_newton.hpp"

namespace num = deformation_enrichment::numerics;
namespace de = deformation_enrichment;
using Eigen::MatrixXd;
using Eigen::VectorXd;

namespace {

// Rosenbrock's valley: stiff (condition ~2500 at the minimum) and non-convex away from it.
num::NewtonObjective<MatrixXd> rosenbrock() {
  num::NewtonObjective<MatrixXd> f;
  f.evaluate = [](const VectorXd& x, VectorXd* g) {
    const double a = 1.0 - x[0], b = x[1] - x[0] * x[0];
    if (g) *g = Eigen::Vector2d(-2.0 * a - 400.0 * x[0] * b, 200.0 * b);
    return a * a + 100.0 * b * b;
  };
  f.hessian = [](const VectorXd& x) {
    MatrixXd h(2, 2);
    h << 2.0 - 400.0 * (x[1] - 3.0 * x[0] * x[0]), -400.0 * x[0], -400.0 * x[0], 200.0;
    return h;
  };
  return f;
}

}  // namespace

TEST(DampedNewton, NewtonAndBfgsReachTheRosenbrockMinimum) {
  for (bool quasi : {false, true}) {
    VectorXd x = Eigen::Vector2d(-1.2, 1.0);
    num::NewtonOptions options;
    options.maxIterations = 500;
    options.gradientSquaredTolerance = 1e-20;
    options.quasiNewton = quasi;
    const MatrixXd identity = MatrixXd::Identity(2, 2);
    const num::NewtonReport r = num::dampedNewton(rosenbrock(), x, options, quasi ? &identity : nullptr);
    EXPECT_TRUE(r.converged()) << num::toString(r.status) << " quasi " << quasi;
    EXPECT_LT((x - Eigen::Vector2d(1.0, 1.0)).norm(), 1e-6) << "quasi " << quasi;
    EXPECT_LT(r.value, 1e-12);
    if (quasi) {
      EXPECT_LE(r.hessians, 3);  // BFGS updates, a fresh Hessian only when the model stalls
    }
  }
}

// The progress rule stops once the remaining gap is small next to the decrease made: earlier than the
// gradient rule, with the gap (f - 0 at Rosenbrock's minimum) within that bound.
TEST(DampedNewton, TheProgressRuleStopsWhenTheGapIsSmallNextToTheDecrease) {
  for (bool quasi : {false, true}) {
    const MatrixXd identity = MatrixXd::Identity(2, 2);
    num::NewtonOptions options;
    options.maxIterations = 500;
    options.gradientSquaredTolerance = 1e-20;
    options.quasiNewton = quasi;
    VectorXd tight = Eigen::Vector2d(-1.2, 1.0);
    const num::NewtonReport full = num::dampedNewton(rosenbrock(), tight, options, quasi ? &identity : nullptr);
    options.progressDecrementTolerance = 1e-4;
    VectorXd x = Eigen::Vector2d(-1.2, 1.0);
    const double start = rosenbrock().evaluate(x, nullptr);
    const num::NewtonReport r = num::dampedNewton(rosenbrock(), x, options, quasi ? &identity : nullptr);
    EXPECT_EQ(r.status, num::MinimiserStatus::Converged) << "quasi " << quasi;
    EXPECT_LT(r.iterations, full.iterations) << "quasi " << quasi;
    EXPECT_LE(r.decrement, 1e-4 * (start - r.value)) << "quasi " << quasi;
    EXPECT_GT(r.value, 0.0);
    EXPECT_LT(r.value, 1e-4 * (start - r.value)) << "quasi " << quasi;  // the gap: the minimum is 0
  }
}

TEST(DampedNewton, AnIndefiniteHessianIsDampedIntoADescentStep) {
  // f = x^4 / 4 - x^2 / 2 starts at a maximum's flank (f'' < 0) and must still descend to x = 1.
  num::NewtonObjective<MatrixXd> f;
  f.evaluate = [](const VectorXd& x, VectorXd* g) {
    if (g) *g = VectorXd::Constant(1, x[0] * x[0] * x[0] - x[0]);
    return 0.25 * std::pow(x[0], 4) - 0.5 * x[0] * x[0];
  };
  f.hessian = [](const VectorXd& x) { return MatrixXd::Constant(1, 1, 3.0 * x[0] * x[0] - 1.0); };
  VectorXd x = VectorXd::Constant(1, 0.1);
  num::NewtonOptions options;
  options.gradientSquaredTolerance = 1e-24;
  const num::NewtonReport r = num::dampedNewton(f, x, options);
  EXPECT_TRUE(r.converged());
  EXPECT_NEAR(x[0], 1.0, 1e-6);  // f is resolved to 1e-14 relative: x to about its square root
}

TEST(DampedNewton, InfeasibleTrialsAreNeverAccepted) {
  // The unconstrained minimum x = 3 lies where the objective is infinite (x >= 2, as a collapsed triangle).
  num::NewtonObjective<MatrixXd> f;
  int infeasible = 0;
  f.evaluate = [&](const VectorXd& x, VectorXd* g) {
    if (x[0] >= 2.0) {
      ++infeasible;
      return std::numeric_limits<double>::infinity();
    }
    if (g) *g = VectorXd::Constant(1, 2.0 * (x[0] - 3.0));
    return (x[0] - 3.0) * (x[0] - 3.0);
  };
  f.hessian = [](const VectorXd&) { return MatrixXd::Constant(1, 1, 2.0); };
  VectorXd x = VectorXd::Constant(1, 0.0);
  num::NewtonOptions options;
  options.maxIterations = 200;
  const num::NewtonReport r = num::dampedNewton(f, x, options);
  EXPECT_GT(infeasible, 0);
  EXPECT_LT(x[0], 2.0);
  EXPECT_GT(x[0], 1.99);
  EXPECT_TRUE(std::isfinite(r.value));
  EXPECT_NE(r.status, num::MinimiserStatus::Converged);  // the gradient never vanishes
}

TEST(DampedNewton, SparseNewtonSolvesAQuadraticInOneStepAndReportsNonConvergence) {
  const int n = 50;
  Eigen::SparseMatrix<double> a(n, n);
  std::vector<Eigen::Triplet<double>> t;
  for (int i = 0; i < n; ++i) {
    t.emplace_back(i, i, 4.0);
    if (i + 1 < n) t.emplace_back(i + 1, i, -1.0), t.emplace_back(i, i + 1, -1.0);
  }
  a.setFromTriplets(t.begin(), t.end());
  const VectorXd b = VectorXd::LinSpaced(n, -1.0, 1.0);
  num::NewtonObjective<Eigen::SparseMatrix<double>> f;
  f.evaluate = [&](const VectorXd& x, VectorXd* g) {
    if (g) *g = a * x - b;
    return 0.5 * x.dot(a * x) - b.dot(x);
  };
  f.hessian = [&](const VectorXd&) { return a; };
  VectorXd x = VectorXd::Zero(n);
  num::NewtonOptions options;
  options.gradientSquaredTolerance = 1e-20;
  const num::NewtonReport r = num::dampedNewton(f, x, options);
  EXPECT_TRUE(r.converged());
  EXPECT_LE(r.iterations, 2);
  EXPECT_LT((a * x - b).norm(), 1e-9);

  VectorXd y = Eigen::Vector2d(-1.2, 1.0);
  num::NewtonOptions one;
  one.maxIterations = 1;
  const double start = rosenbrock().evaluate(y, nullptr);
  const num::NewtonReport stopped = num::dampedNewton(rosenbrock(), y, one);
  EXPECT_EQ(stopped.status, num::MinimiserStatus::NotConverged);
  EXPECT_EQ(stopped.iterations, 1);
  EXPECT_LT(stopped.value, start);
  EXPECT_DOUBLE_EQ(stopped.value, rosenbrock().evaluate(y, nullptr));  // x is the accepted iterate
}

TEST(DampedNewton, BadInputGivesClearErrors) {
  num::NewtonObjective<MatrixXd> nan;
  nan.evaluate = [](const VectorXd&, VectorXd* g) {
    if (g) *g = VectorXd::Zero(1);
    return std::numeric_limits<double>::quiet_NaN();
  };
  nan.hessian = [](const VectorXd&) { return MatrixXd::Identity(1, 1); };
  VectorXd x = VectorXd::Zero(1);
  EXPECT_THROW(num::dampedNewton(nan, x, num::NewtonOptions{}), de::NumericalError);
  num::NewtonObjective<Eigen::SparseMatrix<double>> sparse;
  sparse.evaluate = [](const VectorXd& y, VectorXd* g) {
    if (g) *g = y;
    return 0.5 * y.squaredNorm();
  };
  sparse.hessian = [](const VectorXd& y) {
    Eigen::SparseMatrix<double> h(y.size(), y.size());
    h.setIdentity();
    return h;
  };
  num::NewtonOptions quasi;
  quasi.quasiNewton = true;
  EXPECT_THROW(num::dampedNewton(sparse, x, quasi), de::InvalidInputError);
}
