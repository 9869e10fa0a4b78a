#include "deformation_enrichment/shape_space/reduced_average.hpp"

#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>

#include <Eigen/SparseCore>
#include <LBFGS.h>

#include "deformation_enrichment/error.hpp"

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
  const Eigen::SparseMatrix<double> h = energy.hessianDeformed(reference, reference);
  const Eigen::MatrixXd& b = *space.basis;
  Eigen::MatrixXd hr = b.transpose() * (h * b);
  hr = 0.5 * (hr + hr.transpose());
  // Rigid motions inside the subspace make hr singular. The ridge must not be tiny: the objective's rigid
  // null space sits at the unknown shape, not at the reference, and a near-singular preconditioner would
  // blow those slightly different directions up (measured: 1e-8 stalls L-BFGS, 1e-3 converges).
  const double ridge = ridgeFactor * std::max(hr.diagonal().cwiseAbs().mean(), 1e-300);
  hr.diagonal().array() += ridge;
  space.preconditioner.compute(hr);
  if (space.preconditioner.info() != Eigen::Success)
    throw NumericalError("reduced space: the reduced rest Hessian is not positive definite");
  return space;
}

AverageResult reducedElasticAverage(const DeformationEnergy& energy, const std::vector<double>& weights,
                                    const std::vector<const Eigen::VectorXd*>& examples, const ReducedSpace& space,
                                    const Eigen::VectorXd& initial, const ReducedAverageOptions& options) {
  const ReducedSpace& sub = space;
  if (initial.size() != sub.origin.size()) throw InvalidInputError("reduced average: initial shape has the wrong size");
  const auto& llt = space.preconditioner;
  const Eigen::MatrixXd lower = llt.matrixL();
  // q = L^-T z, so dF/dz = L^-1 B^T dF/dy.
  const auto lift = [&](const Eigen::VectorXd& z) {
    return Eigen::VectorXd(sub.lift(lower.transpose().triangularView<Eigen::Upper>().solve(z)));
  };
  int evaluations = 0;
  // eq. 10 with an energy that aggregates its references: one pass per evaluation instead of one per example.
  const std::unique_ptr<WeightedReferenceEnergy> aggregated =
      options.symmetric ? nullptr : energy.weightedReferences(weights, examples);
  // The best point seen: L-BFGS may stop on a bad iterate (e.g. after a breakdown of its curvature pairs).
  Eigen::VectorXd best;
  double bestValue = std::numeric_limits<double>::infinity();
  const auto objective = [&](const Eigen::VectorXd& z, Eigen::VectorXd& gradZ) {
    ++evaluations;
    if (!z.allFinite()) throw std::runtime_error("L-BFGS produced a non-finite iterate");
    Eigen::VectorXd gradY;
    double f;
    try {
      f = aggregated ? aggregated->evaluate(lift(z), &gradY)
                     : averageObjective(energy, weights, examples, lift(z), options.symmetric, &gradY);
    } catch (const InvalidInputError&) {  // a line-search trial collapsed a triangle: reject it
      gradZ = Eigen::VectorXd::Zero(z.size());
      return std::numeric_limits<double>::infinity();
    }
    gradZ = lower.triangularView<Eigen::Lower>().solve(sub.basis->transpose() * gradY);
    if (!std::isfinite(f)) return std::numeric_limits<double>::infinity();
    if (f < bestValue) {
      bestValue = f;
      best = z;
    }
    return f;
  };
  Eigen::VectorXd z = lower.transpose() * sub.coordinates(initial);
  Eigen::VectorXd gradZ;
  const double f0 = objective(z, gradZ);
  if (!std::isfinite(f0)) throw NumericalError("reduced average: objective is not finite at the start");
  const double tolerance = std::max(std::sqrt(options.relativeTolerance * std::max(f0, 0.0)), options.absoluteTolerance);

  LBFGSpp::LBFGSParam<double> param;
  param.m = options.memory;
  param.epsilon = tolerance;
  param.epsilon_rel = 0.0;
  param.max_iterations = options.maxIterations;
  param.max_linesearch = 60;
  LBFGSpp::LBFGSSolver<double> solver(param);
  double f = f0;
  int iterations = 0;
  std::string failure;
  try {
    iterations = solver.minimize(objective, z, f);
  } catch (const std::exception& e) {
    failure = e.what();  // typically a line search that cannot progress: judged by the gradient below
  }
  if (!z.allFinite() || !(objective(z, gradZ) <= bestValue)) z = best;
  const double fEnd = objective(z, gradZ);
  const double gnorm = gradZ.norm();
  // A line search that stalls at round-off level is a converged result; anything else is an error.
  const double accepted = failure.empty() ? tolerance : std::max(tolerance, 1e-8 * std::sqrt(std::max(f0, 0.0)));
  if (!(gnorm <= accepted * (1.0 + 1e-9)) || !std::isfinite(fEnd)) {
    char numbers[96];
    std::snprintf(numbers, sizeof(numbers), "reduced gradient norm %.3e, tolerance %.3e", gnorm, accepted);
    throw NumericalError("reduced average: L-BFGS did not converge after " + std::to_string(iterations) +
                         " iterations (" + numbers + (failure.empty() ? "" : ", " + failure) + ")");
  }
  AverageResult result;
  result.reducedCoordinates = lower.transpose().triangularView<Eigen::Upper>().solve(z);
  result.shape = sub.lift(result.reducedCoordinates);
  result.evaluations = evaluations;
  result.objective = fEnd;
  result.iterations = iterations;
  return result;
}

}  // namespace deformation_enrichment::shape_space
