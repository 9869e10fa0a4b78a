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

AverageResult elasticAverage(const DeformationEnergy& energy, const std::vector<double>& weights,
                             const std::vector<const Eigen::VectorXd*>& examples, const Eigen::VectorXd& initial,
                             const AverageOptions& options) {
  checkInputs(weights, examples, initial);
  NewtonObjective<Eigen::SparseMatrix<double>> objective;
  objective.evaluate = [&](const Eigen::VectorXd& y, Eigen::VectorXd* gradient) {
    try {
      return averageObjective(energy, weights, examples, y, options.symmetric, gradient);
    } catch (const InvalidInputError&) {  // a trial step collapsed a triangle: too long
      return std::numeric_limits<double>::infinity();
    }
  };
  objective.hessian = [&](const Eigen::VectorXd& y) {
    return averageHessian(energy, weights, examples, y, options.symmetric);
  };
  AverageResult result;
  result.shape = initial;
  const double f0 = averageObjective(energy, weights, examples, initial, options.symmetric, nullptr);
  NewtonOptions newton;
  newton.maxIterations = options.maxIterations;
  newton.decrementTolerance = options.relativeTolerance * f0;
  newton.gradientSquaredTolerance = options.absoluteGradientTolerance * options.absoluteGradientTolerance;
  const NewtonReport report = dampedNewton(objective, result.shape, newton);
  result.objective = report.value;
  result.iterations = report.iterations;
  result.evaluations = report.evaluations;
  result.status = report.status;
  result.gradientNorm = std::sqrt(report.gradientSquaredNorm);
  return result;
}

}  // namespace deformation_enrichment::shape_space
