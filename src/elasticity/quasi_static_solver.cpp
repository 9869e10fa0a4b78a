#include "deformation_enrichment/elasticity/quasi_static_solver.hpp"

#include <algorithm>
#include <Eigen/IterativeLinearSolvers>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/numerics/armijo_backtracking.hpp"
#include "deformation_enrichment/seconds_since.hpp"

namespace deformation_enrichment::elasticity {
namespace {

using Clock = std::chrono::steady_clock;

// The last Cholesky factorisation as the preconditioner of Eigen's conjugate gradients (the interface its
// IterativeSolverBase expects); the matrix it is given is not factorised.
class FactorPreconditioner {
public:
  void use(const numerics::SparseCholesky& factor) { factor_ = &factor; }
  template <typename Matrix>
  FactorPreconditioner& analyzePattern(const Matrix&) { return *this; }
  template <typename Matrix>
  FactorPreconditioner& factorize(const Matrix&) { return *this; }
  template <typename Matrix>
  FactorPreconditioner& compute(const Matrix&) { return *this; }
  Eigen::VectorXd solve(const Eigen::VectorXd& r) const { return factor_->solve(r); }
  Eigen::ComputationInfo info() const { return factor_ ? Eigen::Success : Eigen::InvalidInput; }

private:
  const numerics::SparseCholesky* factor_ = nullptr;
};

}  // namespace

void DirichletConstraints::add(int vertex, const Eigen::Vector3d& position) {
  vertices.push_back(vertex);
  positions.conservativeResize(3, static_cast<Eigen::Index>(vertices.size()));
  positions.col(positions.cols() - 1) = position;
}

const char* toString(SolverStatus status) {
  switch (status) {
    case SolverStatus::Converged: return "converged";
    case SolverStatus::MaxIterations: return "iteration limit reached";
    case SolverStatus::TimeLimit: return "time limit reached";
    case SolverStatus::LineSearchFailed: return "line search found no decrease";
    case SolverStatus::LinearSolverFailed: return "Newton system could not be factorised";
  }
  return "unknown";
}

/// The reduced system of one constraint set: dof map, Hessian storage (lower triangle) and the
/// factorisation, whose symbolic analysis is reused while the constrained vertex set stays the same.
struct QuasiStaticSolver::Linear {
  explicit Linear(numerics::SparseCholeskyBackend backend) : cholesky(backend) {}

  Eigen::VectorXi dofMap;
  std::vector<int> freeDofs;  ///< global dof of each reduced row
  Eigen::SparseMatrix<double> H;       ///< projected Hessian (lower triangle)
  Eigen::SparseMatrix<double> Hexact;  ///< exact Hessian, same pattern (used near the solution)
  std::vector<Eigen::Index> diagonal;  ///< value index of H(i, i)
  numerics::SparseCholesky cholesky;
  bool factorized = false;  ///< cholesky holds a factorisation of this pattern

  // A solve starts from a fresh factorisation, so its iterates do not depend on what the solver solved before.
  void prepare(const TetFem& fem, const Eigen::VectorXi& map) {
    factorized = false;
    if (map.size() == dofMap.size() && map == dofMap) return;
    dofMap = map;
    H = fem.reducedPattern(dofMap, true);
    Hexact = Eigen::SparseMatrix<double>();  // pattern changed: rebuilt from H on first use
    freeDofs.assign(static_cast<std::size_t>(H.cols()), 0);
    for (Eigen::Index d = 0; d < dofMap.size(); ++d)
      if (dofMap[d] >= 0) freeDofs[static_cast<std::size_t>(dofMap[d])] = static_cast<int>(d);
    diagonal.resize(static_cast<std::size_t>(H.cols()));
    for (Eigen::Index c = 0; c < H.cols(); ++c) diagonal[static_cast<std::size_t>(c)] = H.outerIndexPtr()[c];  // lower: first entry
  }

  /// Factorises M + shift I (M has the pattern of H); true if positive definite.
  bool factorize(const Eigen::SparseMatrix<double>& M, double shift) {
    factorized = cholesky.factorize(M, shift);
    return factorized;
  }
  Eigen::VectorXd solve(const Eigen::VectorXd& rhs) const { return cholesky.solve(rhs); }
};

QuasiStaticSolver::QuasiStaticSolver(const TetFem& fem, SolverOptions settings)
    : fem_(fem), settings_(std::move(settings)), linear_(std::make_unique<Linear>(settings_.linearSolver)) {
  if (settings_.maxIterations < 0 || !(settings_.relativeForceTolerance >= 0.0) || settings_.maxLineSearchSteps < 1 ||
      !(settings_.armijo > 0.0 && settings_.armijo < 1.0) || !(settings_.maxSeconds > 0.0) ||
      !(settings_.exactHessianBelow >= 0.0) || !(settings_.reuseContraction >= 0.0 && settings_.reuseContraction < 1.0) ||
      !(settings_.preconditionedTolerance >= 0.0 && settings_.preconditionedTolerance < 1.0) ||
      settings_.preconditionedIterations < 0)
    throw InvalidInputError("QuasiStaticSolver: invalid settings (limits must be positive, 0 < armijo < 1, "
                            "exactHessianBelow >= 0, 0 <= reuseContraction < 1, 0 <= preconditionedTolerance < 1, "
                            "preconditionedIterations >= 0)");
}

QuasiStaticSolver::~QuasiStaticSolver() = default;

namespace {

// Sizes, finiteness and ranges of solve()'s input; throws InvalidInputError naming the problem.
void checkSolveInput(Eigen::Index V, const Eigen::Matrix3Xd& positions, const DirichletConstraints& constraints,
                     const AnchorSprings& springs) {
  if (positions.cols() != V)
    throw InvalidInputError("QuasiStaticSolver: positions have " + std::to_string(positions.cols()) + " columns for " +
                            std::to_string(V) + " vertices");
  if (!positions.allFinite()) throw InvalidInputError("QuasiStaticSolver: positions contain NaN or Inf");
  if (constraints.positions.cols() != static_cast<Eigen::Index>(constraints.vertices.size()))
    throw InvalidInputError("QuasiStaticSolver: constraint vertices and positions differ in count");
  if (!constraints.positions.allFinite()) throw InvalidInputError("QuasiStaticSolver: constraint positions contain NaN or Inf");
  std::vector<char> seen(static_cast<std::size_t>(V), 0);
  for (int v : constraints.vertices) {
    if (v < 0 || v >= V) throw InvalidInputError("QuasiStaticSolver: constraint vertex " + std::to_string(v) + " out of range");
    if (seen[static_cast<std::size_t>(v)]++) throw InvalidInputError("QuasiStaticSolver: vertex " + std::to_string(v) + " constrained twice");
  }
  springs.validate(V);
}

}  // namespace

/// One call of solve(): the objective (elastic energy plus springs) on the free dofs, and the state of the
/// Newton loop between iterations.
struct QuasiStaticSolver::Run {
  Run(const TetFem& f, const SolverOptions& s, Linear& l, const AnchorSprings& sp, const Eigen::VectorXi& m, Eigen::Matrix3Xd& x,
      SolveResult& r, Clock::time_point t)
      : fem(f), settings(s), linear(l), springs(sp), map(m), positions(x), result(r), start(t) {}

  const TetFem& fem;
  const SolverOptions& settings;
  Linear& linear;
  const AnchorSprings& springs;
  const Eigen::VectorXi& map;
  Eigen::Matrix3Xd& positions;
  SolveResult& result;
  const Clock::time_point start;
  double energy = 0.0, forceNorm = 0.0;
  double energyNoise = 0.0;  ///< round-off level of E
  double exactBelow = 0.0;   ///< |f| below which the exact Hessian is tried
  Eigen::VectorXd g;         ///< reduced gradient at `positions`
  bool hessianCurrent = true;  ///< linear.H holds the projected Hessian at `positions`
  bool reuseNext = false;      ///< next direction from the current factorisation (chord step)

  double totalEnergy(const Eigen::Matrix3Xd& x) const { return fem.energy(x) + springs.energy(x); }

  Eigen::VectorXd totalGradient(const Eigen::Matrix3Xd& x) const {
    Eigen::VectorXd full = fem.gradient(x);
    springs.addGradient(x, full);
    return full;
  }

  // The springs' energy is separable per vertex: its Hessian k_i I adds to the diagonal only.
  void assemble(HessianKind kind, Eigen::SparseMatrix<double>& M) const {
    fem.assembleReduced(positions, map, true, kind, M, nullptr);
    for (std::size_t i = 0; i < springs.vertices.size(); ++i)
      for (int axis = 0; axis < 3; ++axis) {
        const int row = map[3 * springs.vertices[i] + axis];
        if (row >= 0) M.valuePtr()[linear.diagonal[static_cast<std::size_t>(row)]] += springs.stiffness[static_cast<Eigen::Index>(i)];
      }
  }

  void reducedGradient(const Eigen::Matrix3Xd& x, Eigen::VectorXd& reduced) const {
    const Eigen::VectorXd full = totalGradient(x);
    reduced.resize(static_cast<Eigen::Index>(linear.freeDofs.size()));
    for (std::size_t r = 0; r < linear.freeDofs.size(); ++r) reduced[static_cast<Eigen::Index>(r)] = full[linear.freeDofs[r]];
  }

  void applyStep(Eigen::Matrix3Xd& x, const Eigen::VectorXd& step, double alpha) const {
    for (std::size_t r = 0; r < linear.freeDofs.size(); ++r) {
      const int d = linear.freeDofs[r];
      x(d % 3, d / 3) += alpha * step[static_cast<Eigen::Index>(r)];
    }
  }

  // Energy, forces and tolerances at the start.
  void begin() {
    energy = totalEnergy(positions);
    if (!std::isfinite(energy))
      throw InvalidInputError("QuasiStaticSolver: the initial positions give a non-finite energy (extreme deformation)");
    assemble(HessianKind::Projected, linear.H);
    reducedGradient(positions, g);
    result.initialForceNorm = g.norm();
    double absolute = settings.absoluteForceTolerance;
    if (absolute < 0.0) {
      const Eigen::Vector3d extent = fem.rest().vertices.rowwise().maxCoeff() - fem.rest().vertices.rowwise().minCoeff();
      absolute = 1e-12 * fem.maxShearModulus() * extent.squaredNorm();
    }
    result.forceTolerance = std::max(settings.relativeForceTolerance * result.initialForceNorm, absolute);
    forceNorm = result.initialForceNorm;
    // Round-off level of E: each tet's Psi is accurate to ~eps mu' V relative to its O(mu V) terms.
    energyNoise = 1e-14 * fem.maxShearModulus() * fem.restVolumes().sum();
    exactBelow = settings.exactHessianBelow * result.initialForceNorm;
    result.status = forceNorm <= result.forceTolerance ? SolverStatus::Converged : SolverStatus::MaxIterations;
  }

  // A descent direction: the chord step when allowed, else Newton on the exact Hessian near the solution,
  // else on the projected (PSD) one, shifted only when its factorisation reports it is not positive
  // definite (fully crushed tets can make it singular). False when none is found.
  bool direction(IterationRecord& record, Eigen::VectorXd& d) {
    const Clock::time_point phase = Clock::now();
    bool found = false;
    // Chord step: while Newton steps contract the force strongly, the previous factorisation still gives a
    // good direction for the price of a triangular solve (factorising dominates on large meshes).
    if (reuseNext) {
      d = linear.solve(-g);
      found = d.allFinite() && d.dot(g) < 0.0;
      record.reusedFactorization = found;
    }
    if (!found) {
      if (!hessianCurrent) {
        const Clock::time_point assembly = Clock::now();
        assemble(HessianKind::Projected, linear.H);
        record.assemblySeconds += secondsSince(assembly);
        hessianCurrent = true;
      }
      found = exactDirection(record, d) || preconditionedDirection(record, d) || projectedDirection(record, d);
    }
    record.factorSeconds = secondsSince(phase) - record.assemblySeconds;
    return found;
  }

  // Close to a stable equilibrium the exact Hessian is positive definite and gives Newton's quadratic
  // convergence, which the projected one (exact only where every element is convex) loses. Tried once the
  // force is small; when it is indefinite (still far from a stable state, or near a buckling point), tried
  // again once the force has dropped tenfold.
  bool exactDirection(IterationRecord& record, Eigen::VectorXd& d) {
    if (!(settings.exactHessianBelow > 0.0 && forceNorm <= exactBelow)) return false;
    if (linear.Hexact.rows() != linear.H.rows()) linear.Hexact = linear.H;
    assemble(HessianKind::Exact, linear.Hexact);
    ++result.factorizations;
    bool found = false;
    if (linear.factorize(linear.Hexact, 0.0)) {
      d = linear.solve(-g);
      found = d.allFinite() && d.dot(g) < 0.0;
    }
    record.exactHessian = found;
    if (!found) exactBelow = 0.1 * forceNorm;
    return found;
  }

  // Inexact Newton on the projected Hessian: a few conjugate-gradient iterations preconditioned by the last
  // factorisation cost a fraction of a new one, and where the Hessian has changed little they reach the
  // tolerance. Not near the solution, where the exact Hessian's quadratic convergence needs exact solves.
  bool preconditionedDirection(IterationRecord& record, Eigen::VectorXd& d) {
    if (!(settings.preconditionedTolerance > 0.0) || settings.preconditionedIterations < 1 || !linear.factorized ||
        forceNorm <= exactBelow)
      return false;
    Eigen::ConjugateGradient<Eigen::SparseMatrix<double>, Eigen::Lower, FactorPreconditioner> cg;
    cg.preconditioner().use(linear.cholesky);
    cg.setTolerance(settings.preconditionedTolerance);
    cg.setMaxIterations(settings.preconditionedIterations);
    cg.compute(linear.H);
    d = cg.solve(-g);
    if (cg.info() != Eigen::Success || !d.allFinite() || !(d.dot(g) < 0.0)) return false;
    record.conjugateGradientIterations = static_cast<int>(std::max<Eigen::Index>(cg.iterations(), 1));
    return true;
  }

  bool projectedDirection(IterationRecord& record, Eigen::VectorXd& d) {
    double meanDiagonal = 0.0;
    for (Eigen::Index i : linear.diagonal) meanDiagonal += std::abs(linear.H.valuePtr()[i]);
    meanDiagonal = std::max(meanDiagonal / static_cast<double>(linear.diagonal.size()), std::numeric_limits<double>::min());
    for (double shift = 0.0; shift <= 1e3 * meanDiagonal; shift = shift == 0.0 ? 1e-10 * meanDiagonal : shift * 100.0) {
      ++result.factorizations;
      if (!linear.factorize(linear.H, shift)) continue;
      d = linear.solve(-g);
      if (d.allFinite() && d.dot(g) < 0.0) {
        record.regularisation = shift;
        return true;
      }
    }
    return false;
  }

  // Back-tracking line search on the energy (Armijo condition) into `trial`; true when a step is accepted.
  bool lineSearch(const Eigen::VectorXd& d, IterationRecord& record, Eigen::Matrix3Xd& trial, double& alpha, double& trialEnergy) const {
    const Clock::time_point phase = Clock::now();
    // Below the round-off level of E the Armijo test only compares noise: stop back-tracking there.
    const double noise = energyNoise + 1e-12 * std::abs(energy);
    const numerics::ArmijoResult search = numerics::armijoBacktracking(
        [&](double length) {
          trial = positions;
          applyStep(trial, d, length);
          return totalEnergy(trial);
        },
        energy, d.dot(g), {settings.armijo, settings.maxLineSearchSteps, noise});
    record.lineSearchSteps = std::max(search.trials - 1, 0);
    alpha = search.alpha;
    trialEnergy = search.value;
    const bool accepted = search.accepted || acceptFullStepAtRoundOff(d, noise, trial, alpha, trialEnergy);
    record.lineSearchSeconds = secondsSince(phase);
    return accepted;
  }

  // Near the solution the energy decrease drops below the round-off of E; then the full Newton step is
  // accepted if it does not raise E beyond that round-off and it reduces the force norm.
  bool acceptFullStepAtRoundOff(const Eigen::VectorXd& d, double noise, Eigen::Matrix3Xd& trial, double& alpha,
                                double& trialEnergy) const {
    trial = positions;
    applyStep(trial, d, 1.0);
    trialEnergy = totalEnergy(trial);
    if (trialEnergy > energy + noise) return false;
    const Eigen::VectorXd full = totalGradient(trial);
    double norm2 = 0.0;
    for (int dof : linear.freeDofs) norm2 += full[dof] * full[dof];
    if (std::sqrt(norm2) >= forceNorm) return false;
    alpha = 1.0;
    return true;
  }

  // Moves to the accepted trial and records the iteration.
  void accept(Eigen::Matrix3Xd& trial, double alpha, double trialEnergy, IterationRecord& record) {
    positions.swap(trial);
    energy = trialEnergy;
    const Clock::time_point phase = Clock::now();
    reducedGradient(positions, g);
    hessianCurrent = false;
    record.assemblySeconds += secondsSince(phase);
    const double previousForceNorm = forceNorm;
    forceNorm = g.norm();
    reuseNext = settings.reuseContraction > 0.0 && alpha == 1.0 && forceNorm <= settings.reuseContraction * previousForceNorm;
    ++result.iterations;
    record.energy = energy;
    record.forceNorm = forceNorm;
    record.relativeForceNorm = result.initialForceNorm > 0.0 ? forceNorm / result.initialForceNorm : 0.0;
    record.stepLength = alpha;
    record.elapsedSeconds = secondsSince(start);
    result.history.push_back(record);
    if (settings.callback) settings.callback(record);
    if (forceNorm <= result.forceTolerance) result.status = SolverStatus::Converged;
  }
};

SolveResult QuasiStaticSolver::solve(Eigen::Matrix3Xd& positions, const DirichletConstraints& constraints,
                                     const AnchorSprings& springs) {
  const Clock::time_point start = Clock::now();
  checkSolveInput(fem_.numVertices(), positions, constraints, springs);
  int freeCount = 0;
  const Eigen::VectorXi map = makeDofMap(fem_.numVertices(), constraints.vertices, &freeCount);
  if (freeCount == 0) throw InvalidInputError("QuasiStaticSolver: every vertex is constrained");
  for (std::size_t k = 0; k < constraints.vertices.size(); ++k)
    positions.col(constraints.vertices[k]) = constraints.positions.col(static_cast<Eigen::Index>(k));
  linear_->prepare(fem_, map);
  SolveResult result;
  result.freeDofs = freeCount;
  Run run(fem_, settings_, *linear_, springs, map, positions, result, start);
  run.begin();
  Eigen::Matrix3Xd trial;
  while (result.status != SolverStatus::Converged && result.iterations < settings_.maxIterations) {
    if (secondsSince(start) > settings_.maxSeconds) {
      result.status = SolverStatus::TimeLimit;
      break;
    }
    IterationRecord record;
    record.iteration = result.iterations + 1;
    Eigen::VectorXd direction;
    if (!run.direction(record, direction)) {
      result.status = SolverStatus::LinearSolverFailed;
      break;
    }
    double alpha = 1.0, trialEnergy = 0.0;
    if (run.lineSearch(direction, record, trial, alpha, trialEnergy)) {
      run.accept(trial, alpha, trialEnergy, record);
    } else if (record.reusedFactorization) {
      run.reuseNext = false;  // the stale direction was poor: retry with a fresh factorisation
    } else {
      result.status = SolverStatus::LineSearchFailed;
      break;
    }
  }
  result.finalForceNorm = run.forceNorm;
  result.energy = run.energy;
  result.seconds = secondsSince(start);
  std::ostringstream message;
  message << toString(result.status) << " after " << result.iterations << " Newton iterations: |f| = " << run.forceNorm
          << " N (start " << result.initialForceNorm << " N, tolerance " << result.forceTolerance << " N), E = "
          << run.energy << " J, " << result.seconds << " s, " << freeCount << " free dofs";
  result.message = message.str();
  return result;
}

}  // namespace deformation_enrichment::elasticity
