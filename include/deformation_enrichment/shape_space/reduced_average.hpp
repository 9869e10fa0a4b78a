#pragma once
// Reduced elastic averaging ([Brandt16 §6], "Solving the reduced problem"): the unknown shape is restricted
// to an affine subspace y = origin + B q and eq. 10 (or eq. 1) is minimised over q by BFGS with a warm
// start, as the paper does: the Hessian model starts at the reduced rest Hessian B^T d2d2 E(x, x) B of the
// shape's own energy, computed once in a preprocess. The minimiser is the shared damped Newton routine
// (damped_newton.hpp) with BFGS updates; should the model give no descent step, it falls back to the exact
// reduced Hessian (damped Newton).
#include <memory>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "deformation_enrichment/shape_space/deformation_energy.hpp"
#include "deformation_enrichment/shape_space/elastic_average.hpp"

namespace deformation_enrichment::shape_space {

struct ReducedAverageOptions {
  bool symmetric = false;  ///< eq. 1 instead of eq. 10
  int maxIterations = 500;
  /// Converged when the Newton decrement of the BFGS model, g^T H^-1 g (about twice the remaining
  /// objective gap), <= relativeTolerance * objective(start), or <= progressTolerance * (objective(start) -
  /// objective), or |g| <= absoluteTolerance (g the reduced gradient).
  double relativeTolerance = 1e-12;
  /// The gap then is below 5e-7 of the decrease made: the average's error in the energy norm is about 0.1 %
  /// of its distance from the start. Measured: a 140-frame bent sheet's first smoothing step took 523 instead
  /// of 777 iterations, eq. 4 after it the same to 6 digits; 10 steps of the 32 noisy MD2 clips 14354 instead
  /// of 19915 (0 disables the rule).
  double progressTolerance = 1e-6;
  double absoluteTolerance = 1e-14;
};

/// Per-shape reduced space y = origin + basis q with its warm-start Hessian. The basis is shared between
/// the shapes of a sequence (a 15k-vertex, 140-shape sequence would otherwise hold 140 copies of it).
struct ReducedSpace {
  Eigen::VectorXd origin;                        ///< n
  std::shared_ptr<const Eigen::MatrixXd> basis;  ///< n x d, orthonormal columns
  /// d x d start model of the quasi-Newton solver: the reduced rest Hessian (+ small ridge), positive definite;
  /// a caller may replace it by the model a similar average ended with (SmoothingFlow does, step to step).
  Eigen::MatrixXd warmStart;

  Eigen::VectorXd lift(const Eigen::VectorXd& q) const { return origin + *basis * q; }
  Eigen::VectorXd coordinates(const Eigen::VectorXd& y) const { return basis->transpose() * (y - origin); }
};

/// Builds the warm start from the reduced rest Hessian of E(reference, .) at the reference.
/// ridgeFactor times the mean diagonal is added to it (rigid motions make it singular).
/// Throws InvalidInputError for mismatched sizes or an empty basis, NumericalError if the ridged reduced
/// rest Hessian is not positive definite.
ReducedSpace makeReducedSpace(const DeformationEnergy& energy, Eigen::VectorXd origin,
                              std::shared_ptr<const Eigen::MatrixXd> basis, const Eigen::VectorXd& reference,
                              double ridgeFactor = 1e-3);

/// Sets space.warmStart to B^T hessian B made positive definite, e.g. from the Hessian of the objective the
/// space will first be used for (which may be indefinite away from its minimum): each eigenvalue lambda
/// becomes max(|lambda|, ridgeFactor times the mean |diagonal|). Throws InvalidInputError for a Hessian of
/// the wrong size, NumericalError if it is not finite.
void setWarmStart(ReducedSpace& space, const Eigen::SparseMatrix<double>& hessian, double ridgeFactor);

/// Minimises eq. 10 (or eq. 1) over the subspace starting at the projection of `initial`. A run that does
/// not converge returns its last iterate with status NotConverged (never a worse objective than the start).
/// `data`: the examples' DeformationEnergy::referenceData, if the caller keeps it (AverageObjective).
/// Throws InvalidInputError for bad sizes or weights, NumericalError if the objective is not finite at the start.
AverageResult reducedElasticAverage(const DeformationEnergy& energy, const std::vector<double>& weights,
                                    const std::vector<const Eigen::VectorXd*>& examples, const ReducedSpace& space,
                                    const Eigen::VectorXd& initial, const ReducedAverageOptions& options = {},
                                    const std::vector<const ReferenceData*>& data = {});

}  // namespace deformation_enrichment::shape_space
