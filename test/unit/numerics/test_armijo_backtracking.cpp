// The shared Armijo backtracking: accepts the first halving that decreases enough, treats infeasible trials as
// too long, and stops at the objective's resolution or after its trial budget.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "deformation_enrichment/numerics/armijo_backtracking.hpp"

namespace num = deformation_enrichment::numerics;

namespace {

// f(alpha) = (alpha - a)^2 along a line from 0: slope -2a at alpha = 0.
struct Parabola {
  double minimiser;
  std::vector<double> tried;
  double operator()(double alpha) {
    tried.push_back(alpha);
    return (alpha - minimiser) * (alpha - minimiser);
  }
};

}  // namespace

TEST(ArmijoBacktracking, AcceptsTheFullStepWhenItDecreasesEnough) {
  Parabola f{1.0, {}};
  const num::ArmijoResult r = num::armijoBacktracking(std::ref(f), 1.0, -2.0, {});
  EXPECT_TRUE(r.accepted);
  EXPECT_EQ(r.alpha, 1.0);
  EXPECT_EQ(r.value, 0.0);
  EXPECT_EQ(r.trials, 1);
}

TEST(ArmijoBacktracking, HalvesUntilTheSufficientDecreaseTestHolds) {
  // Minimiser at 1/16 with a step of 1: f(1) > f(0); f(1/8) = f(0) exactly, fails c > 0; f(1/16) = 0 passes.
  Parabola f{1.0 / 16.0, {}};
  const double f0 = f.minimiser * f.minimiser;
  const num::ArmijoResult r = num::armijoBacktracking(std::ref(f), f0, -2.0 * f.minimiser, {0.5, 30, 0.0});
  ASSERT_TRUE(r.accepted);
  EXPECT_EQ(r.alpha, 1.0 / 16.0);
  EXPECT_EQ(r.trials, 5);
  EXPECT_EQ(f.tried, (std::vector<double>{1.0, 0.5, 0.25, 0.125, 0.0625}));
  EXPECT_EQ(r.value, 0.0);
}

TEST(ArmijoBacktracking, InfeasibleTrialsCountAsTooLong) {
  std::vector<double> tried;
  const auto f = [&](double alpha) {
    tried.push_back(alpha);
    return alpha > 0.3 ? std::numeric_limits<double>::infinity() : (alpha > 0.2 ? std::nan("") : 1.0 - alpha);
  };
  const num::ArmijoResult r = num::armijoBacktracking(f, 1.0, -1.0, {});
  ASSERT_TRUE(r.accepted);
  EXPECT_EQ(r.alpha, 0.125);  // 1, 0.5: +inf; 0.25: NaN; 0.125: 0.875 <= 1 - 1e-4 * 0.125
  EXPECT_EQ(r.trials, 4);
}

TEST(ArmijoBacktracking, StopsAtTheResolutionAndAtTheTrialBudget) {
  const auto rising = [](double alpha) { return 1.0 + alpha; };  // never passes: every trial is tried
  const num::ArmijoResult budget = num::armijoBacktracking(rising, 1.0, -1.0, {1e-4, 7, 0.0});
  EXPECT_FALSE(budget.accepted);
  EXPECT_EQ(budget.trials, 7);
  EXPECT_EQ(budget.alpha, std::ldexp(1.0, -6));
  // Predicted decreases alpha * 1 of 1, 1/2, 1/4 exceed 0.2; 1/8 does not: three trials.
  const num::ArmijoResult resolved = num::armijoBacktracking(rising, 1.0, -1.0, {1e-4, 30, 0.2});
  EXPECT_FALSE(resolved.accepted);
  EXPECT_EQ(resolved.trials, 3);
  // A slope below the resolution tries nothing.
  EXPECT_EQ(num::armijoBacktracking(rising, 1.0, -1e-3, {1e-4, 30, 1e-2}).trials, 0);
}
