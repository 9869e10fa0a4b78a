#pragma once
// The one ramp every gate of the run time uses, so that no knob or rule switches with a step (a live stream
// must change continuously with its inputs): 0 up to `floor`, 1 from 2 floor on, smoothstep 3t^2 - 2t^3
// between. A floor <= 0 gates nothing but exact zero.
#include <algorithm>

namespace deformation_enrichment {

inline double smoothRamp(double value, double floor) {
  if (!(floor > 0.0)) return value > 0.0 ? 1.0 : 0.0;
  const double t = std::clamp(value / floor - 1.0, 0.0, 1.0);
  return t * t * (3.0 - 2.0 * t);
}

}  // namespace deformation_enrichment
