#pragma once
// Elastic shape averaging ([Brandt16 §3/§6]): A(w, y) = argmin_y sum_i w_i E(y_i, y)   (eq. 10), or the
// symmetric sum_i w_i (E(y_i, y) + E(y, y_i))   (eq. 1). Full-space damped Newton (damped_newton.hpp) with
// a sparse Cholesky factorisation (CHOLMOD when available); the damping is isotropic, so the iteration
// commutes with rigid motions and never moves along the energy's rigid null space (the gradient of a
// rigid-invariant energy is orthogonal to it): results follow rigid motions of the inputs exactly.
#include <cmath>
#include <memory>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "deformation_enrichment/numerics/damped_newton.hpp"
#include "deformation_enrichment/shape_space/deformation_energy.hpp"

namespace deformation_enrichment::shape_space {

struct AverageOptions {
  bool symmetric = false;           ///< eq. 1 instead of eq. 10
  int maxIterations = 100;
  /// Converged when the Newton decrement -g.d <= relativeTolerance * (objective at the start) or the
  /// gradient norm <= absoluteGradientTolerance.
  double relativeTolerance = 1e-12;
  double absoluteGradientTolerance = 1e-12;
};

struct AverageResult {
  Eigen::VectorXd shape;  ///< the last accepted iterate (the start if no step was accepted)
  double objective = 0.0;
  int iterations = 0;
  int evaluations = 0;  ///< objective evaluations
  numerics::MinimiserStatus status = numerics::MinimiserStatus::NotConverged;
  double gradientNorm = 0.0;  ///< |gradient| at shape (reduced solver: of the reduced objective)
  /// Reduced solver only: q with shape = origin + basis q (lets a ghost-mesh solve be lifted to the fine mesh).
  Eigen::VectorXd reducedCoordinates;
  /// Reduced solver only: its quasi-Newton model of the Hessian at the end (a warm start for a similar average).
  Eigen::MatrixXd reducedModel;
  bool converged() const { return status != numerics::MinimiserStatus::NotConverged; }
  /// The solver's outcome: everything but the shape and the reduced solver's fields.
  void record(const numerics::NewtonReport& report) {
    objective = report.value;
    iterations = report.iterations;
    evaluations = report.evaluations;
    status = report.status;
    gradientNorm = std::sqrt(report.gradientSquaredNorm);
  }
};

/// The objective of eq. 10 / eq. 1 prepared once for the solvers: eq. 10 through the energy's aggregated
/// references (DeformationEnergy::weightedReferences: one deformed-only pass per value, gradient or
/// Hessian) when it has them, else term by term. The energy and the examples must outlive it.
class AverageObjective {
public:
  /// Throws InvalidInputError for mismatched sizes, negative/non-finite weights, all-zero weights or
  /// non-finite examples. `data`: the examples' DeformationEnergy::referenceData, if the caller keeps it.
  AverageObjective(const DeformationEnergy& energy, std::vector<double> weights,
                   std::vector<const Eigen::VectorXd*> examples, bool symmetric,
                   const std::vector<const ReferenceData*>& data = {});
  /// The value and, with gradient, its gradient at y; +infinity if y is not admissible (a collapsed
  /// triangle), so a solver treats such a trial as too long.
  double value(const Eigen::VectorXd& y, Eigen::VectorXd* gradient) const;
  Eigen::SparseMatrix<double> hessian(const Eigen::VectorXd& y) const;

private:
  const DeformationEnergy& energy_;
  std::vector<double> weights_;
  std::vector<const Eigen::VectorXd*> examples_;
  bool symmetric_;
  std::unique_ptr<WeightedReferenceEnergy> aggregated_;
};

/// Weighted elastic average of `examples` (flat 3V vectors), Newton started at `initial`.
/// Throws InvalidInputError for mismatched sizes, negative/non-finite weights, an all-zero weight vector or
/// non-finite shapes, NumericalError if the objective is not finite at the start. A run that does not
/// converge within maxIterations returns its last iterate with status NotConverged.
AverageResult elasticAverage(const DeformationEnergy& energy, const std::vector<double>& weights,
                             const std::vector<const Eigen::VectorXd*>& examples, const Eigen::VectorXd& initial,
                             const AverageOptions& options = {});

/// The objective of eq. 10 / eq. 1 and its gradient in y (for checks and the reduced solver).
double averageObjective(const DeformationEnergy& energy, const std::vector<double>& weights,
                        const std::vector<const Eigen::VectorXd*>& examples, const Eigen::VectorXd& y,
                        bool symmetric, Eigen::VectorXd* gradient);

/// The Hessian of that objective in y (both triangles stored).
Eigen::SparseMatrix<double> averageHessian(const DeformationEnergy& energy, const std::vector<double>& weights,
                                           const std::vector<const Eigen::VectorXd*>& examples,
                                           const Eigen::VectorXd& y, bool symmetric);

}  // namespace deformation_enrichment::shape_space
