#pragma once
// Runs CalculiX's ccx (a separate GPL program, never linked) on a CalculixModel in a fresh temporary
// folder, removed afterwards, and reads the displacements back.
#include <Eigen/Core>
#include <string>

#include "deformation_enrichment/elasticity/calculix_deck.hpp"

namespace deformation_enrichment::elasticity {

struct CalculixOptions {
  std::string program = "ccx";  ///< looked up on PATH
  /// OMP_NUM_THREADS and CCX_NPROC_EQUATION_SOLVER of the ccx process (ccx would otherwise take every core).
  int threads = 1;
};

struct CalculixRun {
  Eigen::Matrix3Xd displacements;  ///< 3 x V, at the end of the step
  double seconds = 0.0;            ///< wall-clock time of the ccx process
};

/// Throws InvalidInputError for an invalid model or threads < 1, and IoError naming the deck or output
/// file and the reason when ccx cannot be started (not installed), fails or crashes, reports an *ERROR
/// (a deck it rejects), writes no displacements, or stops before the end of the step (no convergence).
CalculixRun runCalculix(const CalculixModel& model, const CalculixOptions& options = CalculixOptions());

}  // namespace deformation_enrichment::elasticity
