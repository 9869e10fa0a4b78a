#include "deformation_enrichment/shape_space/elastic_average.hpp"

#include <cmath>
#include <limits>
#include <string>

#include <Eigen/SparseCore>
#ifdef DE_HAVE_CHOLMOD
#include <Eigen/CholmodSupport>
#else
#include <Eigen/SparseCholesky>
#endif

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

Eigen::SparseMatrix<double> averageHessian(const DeformationEnergy& energy, const std::vector<double>& weights,
                                           const std::vector<const Eigen::VectorXd*>& examples,
                                           const Eigen::VectorXd& y, bool symmetric) {
  Eigen::SparseMatrix<double> h(y.size(), y.size());
  for (size_t i = 0; i < examples.size(); ++i) {
    if (weights[i] == 0.0) continue;
    h += weights[i] * energy.hessianDeformed(*examples[i], y);          // d2d2 E(y_i, y)
    if (symmetric) h += weights[i] * energy.hessianReference(y, *examples[i]);  // d1d1 E(y, y_i)
  }
  return h;
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

AverageResult elasticAverage(const DeformationEnergy& energy, const std::vector<double>& weights,
                             const std::vector<const Eigen::VectorXd*>& examples, const Eigen::VectorXd& initial,
                             const AverageOptions& options) {
  checkInputs(weights, examples, initial);
  AverageResult result;
  result.shape = initial;
  Eigen::VectorXd gradient;
  double f = averageObjective(energy, weights, examples, result.shape, options.symmetric, &gradient);
  const double f0 = f;
#ifdef DE_HAVE_CHOLMOD
  Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Lower> solver;  // LLT: reports indefinite matrices
#else
  Eigen::SimplicialLLT<Eigen::SparseMatrix<double>, Eigen::Lower> solver;
#endif
#ifdef DE_HAVE_CHOLMOD
  solver.cholmod().print = 0;  // indefinite trial matrices are expected (handled by damping): no warnings
#endif
  bool analysed = false;
  int stalledSteps = 0;
  double damping = 1e-10;  // relative to the mean Hessian diagonal; only kills the rigid null space at first
  for (int it = 0;; ++it) {
    result.iterations = it;
    if (gradient.norm() <= options.absoluteGradientTolerance) break;
    if (it == options.maxIterations)
      throw NumericalError("elastic average: Newton did not converge in " + std::to_string(options.maxIterations) +
                           " iterations (gradient norm " + std::to_string(gradient.norm()) + ")");
    Eigen::SparseMatrix<double> h = averageHessian(energy, weights, examples, result.shape, options.symmetric);
    const double diagScale = std::max(h.diagonal().cwiseAbs().mean(), 1e-300);
    if (!analysed) {
      solver.analyzePattern(h);
      analysed = true;
    }
    // Levenberg-Marquardt: raise the damping until the matrix is positive definite and the step descends.
    Eigen::VectorXd step;
    bool accepted = false;
    for (int attempt = 0; attempt < 40 && !accepted; ++attempt) {
      Eigen::SparseMatrix<double> damped = h;
      for (Eigen::Index k = 0; k < damped.rows(); ++k) damped.coeffRef(k, k) += damping * diagScale;
      solver.factorize(damped);
      if (solver.info() != Eigen::Success) {
        damping *= 10.0;
        continue;
      }
      step = -solver.solve(gradient);
      const double decrement = -gradient.dot(step);
      if (!step.allFinite() || !(decrement > 0.0)) {
        damping *= 10.0;
        continue;
      }
      if (decrement <= options.relativeTolerance * f0) {  // Newton decrement: nothing left to gain
        result.objective = f;
        result.iterations = it;
        return result;
      }
      // Armijo backtracking on the objective.
      double alpha = 1.0;
      for (int ls = 0; ls < 30; ++ls, alpha *= 0.5) {
        const Eigen::VectorXd trial = result.shape + alpha * step;
        Eigen::VectorXd trialGradient;
        double ft = std::numeric_limits<double>::infinity();
        try {
          ft = averageObjective(energy, weights, examples, trial, options.symmetric, &trialGradient);
        } catch (const InvalidInputError&) {
          // The trial step collapsed a triangle (the energy rejects degenerate shapes): step too long.
        }
        if (std::isfinite(ft) && ft <= f - 1e-4 * alpha * decrement) {
          // Progress below the objective's double-precision resolution: count it (see below).
          stalledSteps = (f - ft <= 1e-13 * std::abs(f)) ? stalledSteps + 1 : 0;
          result.shape = trial;
          f = ft;
          gradient = trialGradient;
          accepted = true;
          break;
        }
      }
      if (!accepted) damping *= 10.0;
      else damping = std::max(damping * 0.1, 1e-10);
    }
    if (accepted && stalledSteps >= 3) {
      // Three accepted steps in a row that changed the objective by less than 1e-13 relative: the computed
      // objective cannot be lowered further at double precision (seen on jittered MD2 meshes, whose skinny
      // triangles make the Hessian extremely stiff). A minimiser to working precision; it is flagged.
      result.objective = f;
      result.iterations = it + 1;
      result.stalledAtRoundOff = true;
      return result;
    }
    if (!accepted) {
      // No descent even with heavy damping: either at a minimum up to round-off, or a failure.
      if (gradient.norm() <= 1e-8 * std::max(1.0, std::sqrt(f0))) break;
      throw NumericalError("elastic average: Newton found no descent step at iteration " + std::to_string(it) +
                           " (gradient norm " + std::to_string(gradient.norm()) + ")");
    }
  }
  result.objective = f;
  return result;
}

}  // namespace deformation_enrichment::shape_space
