#include "deformation_enrichment/shape_space/elastic_average.hpp"

#include <cmath>
#include <limits>
#include <string>

#include <Eigen/SparseCore>

#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::shape_space {
namespace {

void checkInputs(const std::vector<double>& weights, const std::vector<const Eigen::VectorXd*>& examples,
                 const Eigen::VectorXd& y) {
  if (weights.size() != examples.size())
    throw InvalidInputError("elastic average: " + std::to_string(weights.size()) + " weights for " +
                            std::to_string(examples.size()) + " shapes");
  if (examples.empty()) throw InvalidInputError("elastic average of no shapes");
  double total = 0.0;
  for (size_t i = 0; i < examples.size(); ++i) {
    if (!(std::isfinite(weights[i]) && weights[i] >= 0.0))
      throw InvalidInputError("elastic average: weight " + std::to_string(i) + " is negative or not finite");
    total += weights[i];
    if (examples[i] == nullptr || examples[i]->size() != y.size())
      throw InvalidInputError("elastic average: shape " + std::to_string(i) + " has a different size");
    if (!examples[i]->allFinite()) throw InvalidInputError("elastic average: shape " + std::to_string(i) + " is not finite");
  }
  if (!(total > 0.0)) throw InvalidInputError("elastic average: all weights are zero");
  if (!y.allFinite()) throw InvalidInputError("elastic average: initial shape is not finite");
}

}  // namespace

double averageObjective(const DeformationEnergy& energy, const std::vector<double>& weights,
                        const std::vector<const Eigen::VectorXd*>& examples, const Eigen::VectorXd& y,
                        bool symmetric, Eigen::VectorXd* gradient) {
  checkInputs(weights, examples, y);
  double value = 0.0;
  if (gradient) gradient->setZero(y.size());
  for (size_t i = 0; i < examples.size(); ++i) {
    if (weights[i] == 0.0) continue;
    double term = 0.0;
    Eigen::VectorXd termGradient;
    EnergyOutputs outputs;  // value and gradient in one pass over the mesh
    outputs.value = &term;
    outputs.gradientDeformed = gradient ? &termGradient : nullptr;
    energy.evaluate(*examples[i], y, outputs);  // eq. 10 term
    value += weights[i] * term;
    if (gradient) *gradient += weights[i] * termGradient;
    if (symmetric) {  // eq. 1's extra term
      EnergyOutputs reverse;
      reverse.value = &term;
      reverse.gradientReference = gradient ? &termGradient : nullptr;
      energy.evaluate(y, *examples[i], reverse);
      value += weights[i] * term;
      if (gradient) *gradient += weights[i] * termGradient;
    }
  }
  return value;
}

Eigen::SparseMatrix<double> averageHessian(const DeformationEnergy& energy, const std::vector<double>& weights,
                                           const std::vector<const Eigen::VectorXd*>& examples,
                                           const Eigen::VectorXd& y, bool symmetric) {
  checkInputs(weights, examples, y);
  Eigen::SparseMatrix<double> h(y.size(), y.size());
  for (size_t i = 0; i < examples.size(); ++i) {
    if (weights[i] == 0.0) continue;
    h += weights[i] * energy.hessianDeformed(*examples[i], y);          // d2d2 E(y_i, y)
    if (symmetric) h += weights[i] * energy.hessianReference(y, *examples[i]);  // d1d1 E(y, y_i)
  }
  return h;
}

AverageObjective::AverageObjective(const DeformationEnergy& energy, std::vector<double> weights,
                                   std::vector<const Eigen::VectorXd*> examples, bool symmetric,
                                   const std::vector<const ReferenceData*>& data)
    : energy_(energy), weights_(std::move(weights)), examples_(std::move(examples)), symmetric_(symmetric) {
  if (examples_.empty() || !examples_.front()) throw InvalidInputError("elastic average of no shapes");
  checkInputs(weights_, examples_, *examples_.front());
  // eq. 10 with an energy that aggregates its references: one pass per evaluation instead of one per example.
  if (!symmetric_) aggregated_ = energy_.weightedReferences(weights_, examples_, data);
}

double AverageObjective::value(const Eigen::VectorXd& y, Eigen::VectorXd* gradient) const {
  try {
    return aggregated_ ? aggregated_->evaluate(y, gradient) : averageObjective(energy_, weights_, examples_, y, symmetric_, gradient);
  } catch (const InvalidInputError&) {
    if (y.size() != examples_.front()->size() || !y.allFinite()) throw;
    return std::numeric_limits<double>::infinity();  // a collapsed triangle
  }
}

Eigen::SparseMatrix<double> AverageObjective::hessian(const Eigen::VectorXd& y) const {
  return aggregated_ ? aggregated_->hessian(y) : averageHessian(energy_, weights_, examples_, y, symmetric_);
}

AverageResult elasticAverage(const DeformationEnergy& energy, const std::vector<double>& weights,
                             const std::vector<const Eigen::VectorXd*>& examples, const Eigen::VectorXd& initial,
                             const AverageOptions& options) {
  checkInputs(weights, examples, initial);
  const AverageObjective average(energy, weights, examples, options.symmetric);
  numerics::NewtonObjective<Eigen::SparseMatrix<double>> objective;
  objective.evaluate = [&](const Eigen::VectorXd& y, Eigen::VectorXd* gradient) { return average.value(y, gradient); };
  objective.hessian = [&](const Eigen::VectorXd& y) { return average.hessian(y); };
  AverageResult result;
  result.shape = initial;
  numerics::NewtonOptions newton;
  newton.name = "elastic average";
  newton.maxIterations = options.maxIterations;
  newton.relativeDecrementTolerance = options.relativeTolerance;
  newton.gradientSquaredTolerance = options.absoluteGradientTolerance * options.absoluteGradientTolerance;
  const numerics::NewtonReport report = numerics::dampedNewton(objective, result.shape, newton);
  result.record(report);
  return result;
}

}  // namespace deformation_enrichment::shape_space
