#pragma once
// Independent check of the SNH quasi-static solver: one CalculixModel solved by ccx (compressible
// neo-Hookean) and by our QuasiStaticSolver (Stable Neo-Hookean), with the same mesh, linear tets, materials
// (E, nu) and Dirichlet conditions, and the difference measured. The two energy forms share their tangent
// at rest, so the difference shrinks with the strain; at finite strain it splits into what the energy
// forms explain and what is left (see energyFormRemainder).
#include <Eigen/Core>
#include <string>

#include "deformation_enrichment/elasticity/calculix_run.hpp"
#include "deformation_enrichment/elasticity/stable_neo_hookean.hpp"

namespace deformation_enrichment::elasticity {

struct CalculixComparisonOptions {
  SnhVariant variant = SnhVariant::Paper;
  /// Our Newton tolerance per load step; the constraints are ramped in model.increments equal steps, as ccx
  /// ramps its step. Tight, so that our solver's error stays far below the figures compared.
  double relativeForceTolerance = 1e-10;
  CalculixOptions calculix;
};

struct CalculixComparison {
  /// RMS over nodes of |u_ours - u_ccx| / RMS over nodes of |u_ours|.
  double relativeDifference = 0.0;
  double rmsDisplacement = 0.0;  ///< RMS over nodes of |u_ours| (m)
  double maxDifference = 0.0;    ///< max over nodes of |u_ours - u_ccx| (m)
  double maxGreenStrain = 0.0;   ///< peak |principal Green strain| (F^T F - I)/2 over tets, ours
  double maxDisplacementGradient = 0.0;  ///< peak spectral norm |F - I|_2 over tets, ours
  /// The relative difference left once u_ccx is moved by the linearised SNH response to the force that
  /// the energy forms differ by at u_ccx: H_snh du = -(g_snh - g_nh)(u_ccx) over free dofs; the part of
  /// relativeDifference the energy forms explain is 1 - energyFormRemainder / relativeDifference.
  double energyFormRemainder = 0.0;
  /// |g_nh(u_ccx)| / |g_snh(u_ccx) - g_nh(u_ccx)| over free dofs: how far ccx's answer is from equilibrium
  /// in its own energy, relative to the force the energy forms differ by (0 = fully converged).
  double calculixResidualRatio = 0.0;
  double calculixSeconds = 0.0;  ///< ccx wall-clock
  double ourSeconds = 0.0;       ///< our solves (all steps), wall-clock
  int ourIterations = 0;         ///< Newton iterations over all steps
  Eigen::Matrix3Xd ourDisplacements, calculixDisplacements;
};

/// Throws what validate(model) and runCalculix throw, and NumericalError when our solver does not
/// converge (naming the step and the solver's message).
CalculixComparison compareWithCalculix(const CalculixModel& model,
                                       const CalculixComparisonOptions& options = CalculixComparisonOptions());

}  // namespace deformation_enrichment::elasticity
