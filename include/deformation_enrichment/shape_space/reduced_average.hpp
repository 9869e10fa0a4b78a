#pragma once
// Reduced elastic averaging ([Brandt16 §6], "Solving the reduced problem"): the unknown shape is restricted
// to an affine subspace y = origin + B q and eq. 10 (or eq. 1) is minimised over q with L-BFGS (LBFGSpp).
// The warm start uses an inverse-Hessian estimate computed once in a preprocess: the reduced rest Hessian
// B^T d2d2 E(x, x) B of the shape's own energy, applied as a change of variables q = L^-T z (H_r = L L^T),
// in which the objective's Hessian is close to the identity so L-BFGS starts with a good metric.
#include <memory>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Cholesky>

#include "deformation_enrichment/shape_space/affine_subspace.hpp"
#include "deformation_enrichment/shape_space/deformation_energy.hpp"
#include "deformation_enrichment/shape_space/elastic_average.hpp"

namespace deformation_enrichment::shape_space {

struct ReducedAverageOptions {
  bool symmetric = false;          ///< eq. 1 instead of eq. 10
  int maxIterations = 500;
  int memory = 8;                  ///< L-BFGS history length
  /// Converged when |grad_z|^2 <= relativeTolerance * objective(start) (|grad_z|^2 ~ twice the remaining
  /// objective gap in the preconditioned variables) or |grad_z| <= absoluteTolerance.
  double relativeTolerance = 1e-12;
  double absoluteTolerance = 1e-14;
};

/// Per-shape reduced space y = origin + basis q with its preconditioner. The basis is shared between the
/// shapes of a sequence (a 15k-vertex, 140-shape sequence would otherwise hold 140 copies of it).
struct ReducedSpace {
  Eigen::VectorXd origin;                        ///< n
  std::shared_ptr<const Eigen::MatrixXd> basis;  ///< n x d, orthonormal columns
  Eigen::LLT<Eigen::MatrixXd> preconditioner;    ///< of the reduced rest Hessian (+ small ridge)

  Eigen::VectorXd lift(const Eigen::VectorXd& q) const { return origin + *basis * q; }
  Eigen::VectorXd coordinates(const Eigen::VectorXd& y) const { return basis->transpose() * (y - origin); }
};

/// Builds the preconditioner from the reduced rest Hessian of E(reference, .) at the reference.
/// ridgeFactor times the mean diagonal is added to it (rigid motions make it singular).
/// Throws InvalidInputError for mismatched sizes or an empty basis.
ReducedSpace makeReducedSpace(const DeformationEnergy& energy, Eigen::VectorXd origin,
                              std::shared_ptr<const Eigen::MatrixXd> basis, const Eigen::VectorXd& reference,
                              double ridgeFactor = 1e-3);

/// Minimises eq. 10 (or eq. 1) over the subspace starting at the projection of `initial`.
/// Throws NumericalError if L-BFGS fails or ends above the tolerance (never returns an unconverged shape).
AverageResult reducedElasticAverage(const DeformationEnergy& energy, const std::vector<double>& weights,
                                    const std::vector<const Eigen::VectorXd*>& examples, const ReducedSpace& space,
                                    const Eigen::VectorXd& initial, const ReducedAverageOptions& options = {});

}  // namespace deformation_enrichment::shape_space
