#pragma once
// Direct minimisation of the discrete path energy (eq. 4) E[x_0..x_K] = sum_k W(x_k, x_k+1) + W(x_k+1, x_k)
// over ALL inner shapes at once, the end shapes fixed (the variational definition of a discrete geodesic,
// [Brandt16 §5]; [Heeren12]). Its critical points are those of the symmetric-average flow (eq. 1,
// Lemma 2), reached without the flow's many small steps:
//  - reduced: inner shape k = o_k + B q_k (o_k its initial value, B shared), BFGS over all q_k started from
//    a quadratic model of the dense reduced Hessian B^T d2E B built from the shapes' rest Hessians (a few
//    hundred unknowns; measured on the finger: L-BFGS with a rest-Hessian preconditioner needed 200-400
//    evaluations, exact Newton about 10 Hessians, each costing as much as 14 gradients); energy and
//    derivatives optionally from the ghost mesh ([Brandt16 §6]) with the same reduced coordinates;
//  - full: damped Newton in R^{3V (K-1)} with a sparse Cholesky factorisation, for checking.
// Both run the shared damped Newton routine (damped_newton.hpp) on eq. 4 (path_energy.hpp).
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "deformation_enrichment/numerics/damped_newton.hpp"
#include "deformation_enrichment/shape_space/deformation_energy.hpp"
#include "deformation_enrichment/shape_space/evaluation_space.hpp"

namespace deformation_enrichment::shape_space {

struct PathSolveOptions {
  int maxIterations = 3000;  ///< Newton / BFGS iterations
  /// Stopping rule ([Brandt16 §6]): |gradient|^2 <= max(absoluteFactor * dof, relativeFactor * |gradient at
  /// the start|^2); reduced mode uses the reduced gradient B^T grad (of the ghost energy if one is given).
  double absoluteFactor = 1e-8;
  double relativeFactor = 1e-10;
};

struct PathSolveReport {
  int iterations = 0;   ///< Newton (full) or BFGS (reduced) iterations
  int evaluations = 0;  ///< evaluations of eq. 4, with derivatives or value only (each 2K energy passes)
  double gradientSquaredNorm = 0.0;  ///< at the end, as in the stopping rule
  double threshold = 0.0;            ///< the stopping rule's bound
  numerics::MinimiserStatus status = numerics::MinimiserStatus::NotConverged;
  bool converged = false;            ///< the rule was met, or no step lowers eq. 4 measurably (status RoundOff)
};

/// Reduced minimisation in place: shapes (fine, ends fixed) become o_k + basis q_k with q minimising eq. 4
/// of the space's energy on its evaluated shapes (the ghost mesh's, if it has one). basis: 3V x d (fine).
/// restHessians: restHessians(space.energy(), shapes) if the caller has them (the start model's), else null.
/// Throws InvalidInputError for mismatched sizes, fewer than 3 shapes or an empty basis and
/// NumericalError if eq. 4 is not finite at the start; an unmet stopping rule is reported (converged).
PathSolveReport minimisePathEnergyReduced(const EvaluationSpace& space, std::vector<Eigen::VectorXd>& shapes,
                                          const Eigen::MatrixXd& basis, const PathSolveOptions& options = {},
                                          const std::vector<Eigen::SparseMatrix<double>>* restHessians = nullptr);

/// Full-space damped Newton (Levenberg-Marquardt, Armijo) on eq. 4 in place. Same errors.
PathSolveReport minimisePathEnergyFull(const DeformationEnergy& energy, std::vector<Eigen::VectorXd>& shapes,
                                       const PathSolveOptions& options = {});

}  // namespace deformation_enrichment::shape_space
