#include "deformation_enrichment/shape_space/reduced_average.hpp"

#include <cmath>
#include <memory>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/SparseCore>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/numerics/damped_newton.hpp"

namespace deformation_enrichment::shape_space {

ReducedSpace makeReducedSpace(const DeformationEnergy& energy, Eigen::VectorXd origin,
                              std::shared_ptr<const Eigen::MatrixXd> basis, const Eigen::VectorXd& reference,
                              double ridgeFactor) {
  if (!basis || basis->cols() == 0) throw InvalidInputError("reduced space: the subspace has dimension 0");
  if (origin.size() != reference.size() || basis->rows() != reference.size())
    throw InvalidInputError("reduced space: subspace and reference shape differ in size");
  ReducedSpace space;
  space.origin = std::move(origin);
  space.basis = std::move(basis);
  // Rigid motions inside the subspace make the reduced Hessian singular. The ridge must not be tiny: the
  // objective's rigid null space sits at the unknown shape, not at the reference, and a near-singular warm
  // start would blow those slightly different directions up (measured: 1e-8 stalls the quasi-Newton solver,
  // 1e-3 converges).
  const Eigen::SparseMatrix<double> h = energy.hessianDeformed(reference, reference);
  const Eigen::MatrixXd& b = *space.basis;
  Eigen::MatrixXd hr = b.transpose() * (h * b);
  hr = 0.5 * (hr + hr.transpose());
  hr.diagonal().array() += ridgeFactor * std::max(hr.diagonal().cwiseAbs().mean(), 1e-300);
  if (Eigen::LLT<Eigen::MatrixXd>(hr).info() != Eigen::Success)
    throw NumericalError("reduced space: the reduced rest Hessian is not positive definite");
  space.warmStart = std::move(hr);
  return space;
}

void setWarmStart(ReducedSpace& space, const Eigen::SparseMatrix<double>& hessian, double ridgeFactor) {
  const Eigen::MatrixXd& b = *space.basis;
  if (hessian.rows() != b.rows() || hessian.cols() != b.rows())
    throw InvalidInputError("reduced space: the Hessian and the subspace differ in size");
  Eigen::MatrixXd hr = b.transpose() * (hessian * b);
  hr = 0.5 * (hr + hr.transpose());
  if (!hr.allFinite()) throw NumericalError("reduced space: the reduced Hessian is not finite");
  // Eigenvalue modification [Nocedal06 §3.4]: |lambda|, at least the ridge (the rigid null space).
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(hr);
  const double ridge = ridgeFactor * std::max(hr.diagonal().cwiseAbs().mean(), 1e-300);
  const Eigen::VectorXd modified = eigen.eigenvalues().cwiseAbs().cwiseMax(ridge);
  space.warmStart = eigen.eigenvectors() * modified.asDiagonal() * eigen.eigenvectors().transpose();
  space.warmStart = 0.5 * (space.warmStart + space.warmStart.transpose()).eval();
}

AverageResult reducedElasticAverage(const DeformationEnergy& energy, const std::vector<double>& weights,
                                    const std::vector<const Eigen::VectorXd*>& examples, const ReducedSpace& space,
                                    const Eigen::VectorXd& initial, const ReducedAverageOptions& options,
                                    const std::vector<const ReferenceData*>& data) {
  if (initial.size() != space.origin.size()) throw InvalidInputError("reduced average: initial shape has the wrong size");
  if (!(options.relativeTolerance >= 0.0 && options.progressTolerance >= 0.0 && options.absoluteTolerance >= 0.0))
    throw InvalidInputError("reduced average: tolerances must be >= 0");
  const Eigen::MatrixXd& basis = *space.basis;
  const AverageObjective average(energy, weights, examples, options.symmetric, data);
  numerics::NewtonObjective<Eigen::MatrixXd> objective;
  objective.evaluate = [&](const Eigen::VectorXd& q, Eigen::VectorXd* gradient) {
    Eigen::VectorXd gradY;
    const double f = average.value(space.lift(q), gradient ? &gradY : nullptr);
    if (gradient && std::isfinite(f)) *gradient = basis.transpose() * gradY;
    return f;
  };
  objective.hessian = [&](const Eigen::VectorXd& q) {  // the damped Newton fallback: B^T H B
    const Eigen::MatrixXd h = basis.transpose() * (average.hessian(space.lift(q)) * basis);
    return Eigen::MatrixXd(0.5 * (h + h.transpose()));
  };
  Eigen::VectorXd q = space.coordinates(initial);
  numerics::NewtonOptions newton;
  newton.name = "reduced average";
  newton.maxIterations = options.maxIterations;
  newton.quasiNewton = true;
  newton.relativeDecrementTolerance = options.relativeTolerance;
  newton.progressDecrementTolerance = options.progressTolerance;
  newton.gradientSquaredTolerance = options.absoluteTolerance * options.absoluteTolerance;
  AverageResult result;
  const numerics::NewtonReport report = numerics::dampedNewton(objective, q, newton, &space.warmStart, &result.reducedModel);
  result.shape = space.lift(q);
  result.reducedCoordinates = std::move(q);
  result.record(report);
  return result;
}

}  // namespace deformation_enrichment::shape_space
