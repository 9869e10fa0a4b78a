#pragma once
// Wall time of a phase, for the timings the solvers and the enrichment report.
#include <chrono>

namespace deformation_enrichment {

/// Seconds of the steady clock since `start`.
inline double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace deformation_enrichment
