#pragma once
// Backtracking line search with the Armijo sufficient-decrease test ([Nocedal06 Alg. 3.1], eq. 3.4), the one
// of every Newton solve of the package (numerics::dampedNewton and elasticity::QuasiStaticSolver).
#include <functional>

namespace deformation_enrichment::numerics {

struct ArmijoOptions {
  double sufficientDecrease = 1e-4;  ///< c in f(alpha) <= f(0) + c alpha f'(0)
  int maxTrials = 30;                ///< step lengths tried: 1, 1/2, 1/4, ...
  /// The objective's resolution: backtracking stops once the predicted decrease alpha |f'(0)| is no larger
  /// (below it the test would only compare round-off).
  double resolution = 0.0;
};

struct ArmijoResult {
  bool accepted = false;
  double alpha = 0.0;  ///< the accepted step length (the last one tried if none was accepted)
  double value = 0.0;  ///< the objective there
  int trials = 0;      ///< step lengths tried
};

/// Halves alpha from 1 until objectiveAt(alpha) <= value + c alpha slope. `slope` is the directional derivative
/// at alpha = 0 (negative for a descent direction); a non-finite trial value (outside the objective's domain)
/// counts as too long a step.
ArmijoResult armijoBacktracking(const std::function<double(double alpha)>& objectiveAt, double value, double slope,
                                const ArmijoOptions& options);

}  // namespace deformation_enrichment::numerics
