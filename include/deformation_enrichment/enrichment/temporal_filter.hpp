#pragma once
// An online temporal filter on the added displacement field e of eq. (1) (none of the method's sources
// filters in time): per vertex a first-order low-pass, e_f <- e_f + alpha (e - e_f) with
// alpha = 1 - exp(-dt / tau), the exact discretisation of tau de_f/dt = e - e_f for any frame interval dt.
// It smooths what is left of frame-to-frame jitter at the price of lag: after a step, exp(-k dt / tau) of
// the old field remains k frames later. Work is proportional to the vertices touched now or still fading.
#include <Eigen/Core>
#include <vector>

#include "deformation_enrichment/enrichment/stamp_blending.hpp"

namespace deformation_enrichment::enrichment {

class TemporalFilter {
public:
  /// Vertices whose filtered displacement fades below this (metres) leave the field.
  static constexpr double kFloor = 1e-9;

  /// `timeConstant` tau in seconds; 0 = off. Throws InvalidInputError for a negative or non-finite tau.
  explicit TemporalFilter(double timeConstant = 0.0);
  double timeConstant() const { return tau_; }
  /// A new tau (run-time knob) restarts the filter. Throws as the constructor.
  void setTimeConstant(double seconds);

  /// Filters `field`, the enrichment of a surface of `numVertices`, in place; `dt` seconds since the last
  /// call. Off, a first call, a new vertex count or a dt that is not positive and finite (stamps going
  /// backwards) restart the filter from `field`, which passes unchanged.
  void filter(SurfaceEnrichment& field, double dt, Eigen::Index numVertices);
  void reset();
  /// Whether displacements are still fading (a state without contacts must still be filtered).
  bool fading() const { return !active_.empty(); }

private:
  double tau_ = 0.0;
  Eigen::Matrix3Xd state_;   // e_f at every vertex (zero where inactive); empty while off or restarted
  std::vector<int> active_;  // ascending vertices where e_f is non-zero
};

}  // namespace deformation_enrichment::enrichment
