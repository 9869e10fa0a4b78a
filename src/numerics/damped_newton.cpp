#include "deformation_enrichment/numerics/damped_newton.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <type_traits>

#include <Eigen/Cholesky>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/numerics/armijo_backtracking.hpp"
#include "deformation_enrichment/numerics/sparse_cholesky.hpp"

namespace deformation_enrichment::numerics {
namespace {

using Sparse = Eigen::SparseMatrix<double>;

constexpr double kMinDamping = 1e-10;  // relative to the mean diagonal: at first only the rigid null space
constexpr int kDampingAttempts = 40;   // x10 each: up to 1e30, where the step is scaled steepest descent
constexpr int kHalvings = 30;          // Armijo backtracking trials per attempt
constexpr double kArmijo = 1e-4;

// Cholesky factorisation of H + shift I; fails for indefinite matrices (the caller then raises the shift).
// Dense here, sparse in SparseCholesky.
template <class Matrix>
class ShiftedCholesky;

template <>
class ShiftedCholesky<Eigen::MatrixXd> {
public:
  bool factorize(const Eigen::MatrixXd& h, double shift) {
    Eigen::MatrixXd shifted = h;
    shifted.diagonal().array() += shift;
    llt_.compute(shifted);
    return llt_.info() == Eigen::Success;
  }
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const { return llt_.solve(b); }

private:
  Eigen::LLT<Eigen::MatrixXd> llt_;
};

template <>
class ShiftedCholesky<Sparse> : public SparseCholesky {};

double meanAbsDiagonal(const Eigen::MatrixXd& h) { return std::max(h.diagonal().cwiseAbs().mean(), 1e-300); }
double meanAbsDiagonal(const Sparse& h) { return std::max(Eigen::VectorXd(h.diagonal()).cwiseAbs().mean(), 1e-300); }

// The smallest decrease the computed objective resolves.
double resolution(double f) { return 1e-14 * std::abs(f) + std::numeric_limits<double>::min(); }

enum class StepOutcome { Accepted, Converged, RoundOff, NoDescent };

struct Step {
  StepOutcome outcome = StepOutcome::NoDescent;
  Eigen::VectorXd direction;
  double alpha = 0.0, value = 0.0;
  Eigen::VectorXd gradient;  // at the accepted point if alpha == 1 (else empty)
};

// Levenberg-Marquardt: raise the damping until the shifted model is positive definite and its step
// descends and passes the Armijo test [Nocedal06 §3.1] within kHalvings halvings; a step whose predicted
// decrease is below the objective's resolution means no measurable progress is left (RoundOff).
template <class Matrix>
Step searchStep(const NewtonObjective<Matrix>& objective, const Eigen::VectorXd& x, double f, const Eigen::VectorXd& g,
                const Matrix& h, ShiftedCholesky<Matrix>& cholesky, double& damping, const NewtonOptions& options,
                NewtonReport& report) {
  Step step;
  const double scale = meanAbsDiagonal(h);
  for (int attempt = 0; attempt < kDampingAttempts; ++attempt, damping *= 10.0) {
    if (!cholesky.factorize(h, damping * scale)) continue;
    step.direction = -cholesky.solve(g);
    const double decrement = -g.dot(step.direction);
    if (!step.direction.allFinite() || !(decrement > 0.0)) continue;
    report.decrement = decrement;
    if (decrement <= options.decrementTolerance) {
      step.outcome = StepOutcome::Converged;
      return step;
    }
    if (decrement <= resolution(f)) {
      step.outcome = StepOutcome::RoundOff;
      return step;
    }
    // The full step is usually accepted: try it with the gradient, shorter ones by value only.
    Eigen::VectorXd trialGradient;
    const ArmijoResult search = armijoBacktracking(
        [&](double alpha) {
          ++report.evaluations;
          return objective.evaluate(x + alpha * step.direction, alpha == 1.0 ? &trialGradient : nullptr);
        },
        f, -decrement, {kArmijo, kHalvings, resolution(f)});
    if (search.accepted) {
      step.outcome = StepOutcome::Accepted;
      step.alpha = search.alpha;
      step.value = search.value;
      if (search.alpha == 1.0) step.gradient = std::move(trialGradient);
      return step;
    }
  }
  return step;
}

// BFGS update of a dense Hessian model, skipped when s.y <= 0 keeps it positive definite [Nocedal06 §6.1].
void updateBfgs(Eigen::MatrixXd& h, const Eigen::VectorXd& s, const Eigen::VectorXd& y) {
  const Eigen::VectorXd hs = h * s;
  const double ys = y.dot(s), shs = s.dot(hs);
  if (ys > 1e-12 * std::sqrt(y.squaredNorm() * s.squaredNorm()) && shs > 0.0)
    h += (y * y.transpose()) / ys - (hs * hs.transpose()) / shs;
}

}  // namespace

const char* toString(MinimiserStatus status) {
  switch (status) {
    case MinimiserStatus::Converged: return "converged";
    case MinimiserStatus::RoundOff: return "converged to round-off";
    case MinimiserStatus::NotConverged: return "not converged";
  }
  return "unknown";
}

template <class Matrix>
NewtonReport dampedNewton(const NewtonObjective<Matrix>& objective, Eigen::VectorXd& x, const NewtonOptions& given,
                          const Matrix* initialModel, Matrix* finalModel) {
  constexpr bool kDense = std::is_same_v<Matrix, Eigen::MatrixXd>;
  if (given.quasiNewton && !kDense) throw InvalidInputError(std::string(given.name) + ": BFGS updates need a dense Hessian model");
  NewtonReport report;
  Eigen::VectorXd g;
  double f = objective.evaluate(x, &g);
  ++report.evaluations;
  if (!std::isfinite(f) || !g.allFinite()) throw NumericalError(std::string(given.name) + ": the objective is not finite at the start");
  NewtonOptions options = given;  // the relative rules resolved at the start
  options.gradientSquaredTolerance = std::max(given.gradientSquaredTolerance, given.relativeGradientSquaredTolerance * g.squaredNorm());
  options.decrementTolerance = std::max(given.decrementTolerance, given.relativeDecrementTolerance * f);
  report.gradientSquaredThreshold = options.gradientSquaredTolerance;
  const double fixedDecrementTolerance = options.decrementTolerance, start = f;
  Matrix h = initialModel ? *initialModel : objective.hessian(x);
  report.hessians += initialModel ? 0 : 1;
  bool fresh = initialModel == nullptr;  // h is the Hessian (model) at x, not an update
  ShiftedCholesky<Matrix> cholesky;
  double damping = kMinDamping;
  int tinySteps = 0;
  const auto finish = [&](MinimiserStatus status) {
    if (finalModel) *finalModel = h;
    report.status = status;
    report.value = f;
    report.gradientSquaredNorm = g.squaredNorm();
    return report;
  };
  for (;;) {
    if (g.squaredNorm() <= options.gradientSquaredTolerance) return finish(MinimiserStatus::Converged);
    if (report.iterations >= options.maxIterations) return finish(MinimiserStatus::NotConverged);
    options.decrementTolerance = std::max(fixedDecrementTolerance, given.progressDecrementTolerance * (start - f));
    Step step = searchStep(objective, x, f, g, h, cholesky, damping, options, report);
    if (step.outcome == StepOutcome::Converged) return finish(MinimiserStatus::Converged);
    if (step.outcome == StepOutcome::RoundOff) return finish(MinimiserStatus::RoundOff);
    if (step.outcome == StepOutcome::NoDescent) {
      if (fresh) return finish(MinimiserStatus::NotConverged);
      h = objective.hessian(x);  // the model went stale: start again from the Hessian
      ++report.hessians;
      fresh = true;
      damping = kMinDamping;
      continue;
    }
    ++report.iterations;
    const Eigen::VectorXd s = step.alpha * step.direction, gOld = g;
    x += s;
    // Three accepted steps in a row below 1e-13 relative: the objective cannot be lowered further at double
    // precision (seen on 8-bit quantised MD2 meshes, whose skinny triangles make the Hessian very stiff).
    tinySteps = f - step.value <= 1e-13 * std::abs(f) ? tinySteps + 1 : 0;
    f = step.value;
    if (step.gradient.size() > 0) {
      g = std::move(step.gradient);
    } else {
      f = objective.evaluate(x, &g);
      ++report.evaluations;
    }
    if (tinySteps >= 3) return finish(MinimiserStatus::RoundOff);
    damping = std::max(damping * 0.1, kMinDamping);
    if constexpr (kDense) {
      if (options.quasiNewton) {
        updateBfgs(h, s, g - gOld);
        fresh = false;
        continue;
      }
    }
    h = objective.hessian(x);
    ++report.hessians;
  }
}

template NewtonReport dampedNewton<Eigen::MatrixXd>(const NewtonObjective<Eigen::MatrixXd>&, Eigen::VectorXd&,
                                                    const NewtonOptions&, const Eigen::MatrixXd*, Eigen::MatrixXd*);
template NewtonReport dampedNewton<Sparse>(const NewtonObjective<Sparse>&, Eigen::VectorXd&, const NewtonOptions&,
                                           const Sparse*, Sparse*);

}  // namespace deformation_enrichment::numerics
