#pragma once
// A general damped Newton minimiser ([Nocedal06 §3.4]), i.e. Levenberg-Marquardt damping of a Hessian (or of
// a BFGS-updated Hessian model, [Brandt16 §6] "Solving the reduced problem") and the Armijo backtracking of
// armijo_backtracking.hpp. The shape space minimises with it: the elastic averages (eq. 10 / eq. 1) and the
// path energy (eq. 4), each in full and reduced space. The tet simulator's QuasiStaticSolver shares its line
// search and sparse Cholesky but keeps its own iteration, which reuses factorisations between steps and
// switches to the exact Hessian near equilibrium.
//
// It cannot fail on a descent direction: the damping is raised until the factorisation succeeds and the
// step descends, and the backtracking halves the step until the Armijo test holds or the predicted decrease
// drops below the objective's double-precision resolution (then the point is a minimiser to working
// precision, reported as RoundOff). Infeasible trials (the objective returns +infinity, e.g. a collapsed
// triangle) count as too long. The iterate only ever moves to points with a lower objective.
#include <functional>

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace deformation_enrichment::numerics {

enum class MinimiserStatus {
  Converged,    ///< a stopping rule was met
  RoundOff,     ///< no step lowers the objective measurably: a minimiser to double precision, rules unmet
  NotConverged  ///< out of iterations, or no descent even with heavy damping and a fresh Hessian
};

const char* toString(MinimiserStatus status);

struct NewtonOptions {
  int maxIterations = 100;
  double gradientSquaredTolerance = 0.0;  ///< converged when |g|^2 <= this
  double decrementTolerance = 0.0;        ///< or when the Newton decrement -g.d <= this
  /// The same rules relative to the start, resolved by the minimiser's first evaluation (a caller that
  /// evaluated the start itself would pay that evaluation twice); the larger of each pair applies.
  double relativeGradientSquaredTolerance = 0.0;  ///< |g|^2 <= this * |g(start)|^2
  double relativeDecrementTolerance = 0.0;        ///< -g.d <= this * f(start)
  /// Or when -g.d <= this * (f(start) - f): the remaining gap (about half the decrement) is small next to
  /// the decrease made, so the iterate's error is small next to its distance from the start (a rule that
  /// tightens by itself where a problem starts near its minimiser).
  double progressDecrementTolerance = 0.0;
  const char* name = "damped Newton";             ///< the solver named in errors
  /// Dense problems: between Hessians, update the model by BFGS (kept positive definite by skipping pairs
  /// with s.y <= 0); a new Hessian is taken only when the model yields no descent step.
  bool quasiNewton = false;
};

struct NewtonReport {
  MinimiserStatus status = MinimiserStatus::NotConverged;
  int iterations = 0;   ///< accepted steps
  int evaluations = 0;  ///< calls of evaluate (with or without gradient)
  int hessians = 0;     ///< calls of hessian
  double value = 0.0;
  double gradientSquaredNorm = 0.0;
  double decrement = 0.0;  ///< -g.d of the last computed step (0 if none)
  double gradientSquaredThreshold = 0.0;  ///< the |g|^2 rule that applied (options resolved at the start)
  bool converged() const { return status != MinimiserStatus::NotConverged; }
};

template <class Matrix>
struct NewtonObjective {
  /// The value at x and, if gradient is not null, the gradient; +infinity outside the domain.
  std::function<double(const Eigen::VectorXd& x, Eigen::VectorXd* gradient)> evaluate;
  /// The Hessian at x or a positive semi-definite model of it (sparse: the lower triangle is read).
  std::function<Matrix(const Eigen::VectorXd& x)> hessian;
};

/// Minimises from x in place (x ends at the last accepted iterate). initialModel, if given, replaces the
/// first Hessian (e.g. a rest-shape Hessian as BFGS warm start). Throws NumericalError (naming options.name)
/// if the objective is not finite at the start.
template <class Matrix>
NewtonReport dampedNewton(const NewtonObjective<Matrix>& objective, Eigen::VectorXd& x, const NewtonOptions& options,
                          const Matrix* initialModel = nullptr, Matrix* finalModel = nullptr);

extern template NewtonReport dampedNewton<Eigen::MatrixXd>(const NewtonObjective<Eigen::MatrixXd>&, Eigen::VectorXd&,
                                                           const NewtonOptions&, const Eigen::MatrixXd*, Eigen::MatrixXd*);
extern template NewtonReport dampedNewton<Eigen::SparseMatrix<double>>(const NewtonObjective<Eigen::SparseMatrix<double>>&,
                                                                       Eigen::VectorXd&, const NewtonOptions&,
                                                                       const Eigen::SparseMatrix<double>*,
                                                                       Eigen::SparseMatrix<double>*);

}  // namespace deformation_enrichment::numerics
