#include "deformation_enrichment/numerics/armijo_backtracking.hpp"

#include <cmath>

namespace deformation_enrichment::numerics {

ArmijoResult armijoBacktracking(const std::function<double(double alpha)>& objectiveAt, double value, double slope,
                                const ArmijoOptions& options) {
  ArmijoResult result;
  double alpha = 1.0;
  for (; result.trials < options.maxTrials && alpha * std::abs(slope) > options.resolution; alpha *= 0.5) {
    const double trial = objectiveAt(alpha);
    ++result.trials;
    result.alpha = alpha;
    result.value = trial;
    if (std::isfinite(trial) && trial <= value + options.sufficientDecrease * alpha * slope) {  // [Nocedal06 eq. 3.4]
      result.accepted = true;
      return result;
    }
  }
  return result;
}

}  // namespace deformation_enrichment::numerics
