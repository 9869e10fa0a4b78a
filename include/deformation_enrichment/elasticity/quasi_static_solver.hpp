#pragma once
// Quasi-static equilibrium of a TetFem body under Dirichlet constraints: minimise E(x) over the free
// vertices with Newton's method on the PSD-projected Hessian (the analytic eigensystem of [Masanti19]
// §3.3.5 clamps each element's negative modes, so every Newton system is positive semi-definite),
// sparse Cholesky, and the Armijo back-tracking line search on the energy (both in numerics/).
#include <Eigen/Core>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "deformation_enrichment/elasticity/anchor_springs.hpp"
#include "deformation_enrichment/elasticity/tet_fem.hpp"
#include "deformation_enrichment/numerics/sparse_cholesky.hpp"

namespace deformation_enrichment::elasticity {

/// Vertices held at given positions (support: their rest positions; tool: prescribed positions).
struct DirichletConstraints {
  std::vector<int> vertices;
  Eigen::Matrix3Xd positions;  ///< 3 x vertices.size()

  void add(int vertex, const Eigen::Vector3d& position);
};

/// One Newton iteration, as reported to the callback and kept in the result.
struct IterationRecord {
  int iteration = 0;
  double energy = 0.0;             ///< after the step
  double forceNorm = 0.0;          ///< |dE/dx| over free dofs, after the step
  double relativeForceNorm = 0.0;  ///< forceNorm / initial force norm
  double stepLength = 0.0;         ///< accepted line-search factor
  int lineSearchSteps = 0;         ///< halvings
  double regularisation = 0.0;     ///< diagonal shift that made the system positive definite (0 usually)
  bool exactHessian = false;       ///< the step used the exact (not projected) Hessian
  bool reusedFactorization = false;  ///< chord step: the previous iteration's factorisation was reused
  int conjugateGradientIterations = 0;  ///< > 0: the direction came from conjugate gradients preconditioned by it
  double assemblySeconds = 0.0, factorSeconds = 0.0, lineSearchSeconds = 0.0;
  double elapsedSeconds = 0.0;     ///< since the solve began
};

enum class SolverStatus { Converged, MaxIterations, TimeLimit, LineSearchFailed, LinearSolverFailed };
const char* toString(SolverStatus status);

struct SolverOptions {
  int maxIterations = 100;
  double maxSeconds = 1e30;
  /// Converged when |f| <= max(relativeForceTolerance |f_0|, absoluteForceTolerance) where f are the
  /// free-dof forces and f_0 those at the start (after the constraints are applied).
  double relativeForceTolerance = 1e-8;
  /// Absolute floor in newtons; negative = automatic, 1e-12 mu_max L^2 (L = rest bounding-box diagonal).
  double absoluteForceTolerance = -1.0;
  int maxLineSearchSteps = 40;
  double armijo = 1e-4;  ///< sufficient-decrease constant
  /// Once |f| <= exactHessianBelow |f_0|, try the exact Hessian first (used only if its Cholesky
  /// factorisation succeeds, i.e. it is positive definite; after a failure, again once |f| has dropped
  /// tenfold); 0 = always the projected Hessian.
  double exactHessianBelow = 1e-2;
  /// After a full step that shrank |f| to at most this fraction, the next direction reuses the current
  /// factorisation (chord step, one triangular solve); a chord step that does not contract as much, or
  /// fails the line search, triggers a fresh factorisation. 0 = factorise every iteration.
  double reuseContraction = 0.25;
  /// Where a fresh factorisation would follow, first try conjugate gradients on the current projected
  /// Hessian preconditioned by the last factorisation (inexact Newton [Nocedal06 §7.1]): the direction is
  /// kept when the relative residual falls below this within `preconditionedIterations` iterations, else
  /// the Hessian is factorised as before. 0 = always factorise.
  double preconditionedTolerance = 0.1;
  int preconditionedIterations = 8;
  numerics::SparseCholeskyBackend linearSolver = numerics::SparseCholeskyBackend::Default;
  std::function<void(const IterationRecord&)> callback;  ///< optional, called after each iteration
};

struct SolveResult {
  SolverStatus status = SolverStatus::MaxIterations;
  bool converged() const { return status == SolverStatus::Converged; }
  int iterations = 0;
  double initialForceNorm = 0.0;
  double finalForceNorm = 0.0;
  double forceTolerance = 0.0;  ///< the threshold actually used
  double energy = 0.0;
  double seconds = 0.0;
  int freeDofs = 0;
  int factorizations = 0;  ///< numeric Cholesky factorisations, including rejected (not positive definite) ones
  std::string message;  ///< human-readable summary; says why when not converged
  std::vector<IterationRecord> history;
};

class QuasiStaticSolver {
public:
  /// Keeps a reference to `fem`, which must outlive the solver. Throws InvalidInputError for
  /// SparseCholeskyBackend::Cholmod when the library was built without CHOLMOD.
  explicit QuasiStaticSolver(const TetFem& fem, SolverOptions settings = SolverOptions());
  ~QuasiStaticSolver();
  QuasiStaticSolver(const QuasiStaticSolver&) = delete;
  QuasiStaticSolver& operator=(const QuasiStaticSolver&) = delete;

  /// Moves `positions` (3 x V, the initial guess, e.g. the previous step) to equilibrium: constrained
  /// vertices are set to their prescribed positions, the others are solved for. The energy never rises
  /// by more than its round-off level (1e-14 mu_max V + 1e-12 |E|; steps below it are accepted when they
  /// reduce the force). On failure `positions` holds the last accepted iterate (finite, no higher energy
  /// than the start) and the result says why.
  /// `springs` add penalty anchors to the energy (springs on constrained vertices have no effect).
  /// Throws InvalidInputError for wrong sizes, non-finite input, out-of-range or repeated constraint
  /// vertices, invalid springs, or no free vertex.
  SolveResult solve(Eigen::Matrix3Xd& positions, const DirichletConstraints& constraints,
                    const AnchorSprings& springs = AnchorSprings());

  const SolverOptions& settings() const { return settings_; }
  SolverOptions& settings() { return settings_; }

private:
  struct Linear;
  struct Run;
  const TetFem& fem_;
  SolverOptions settings_;
  std::unique_ptr<Linear> linear_;
};

}  // namespace deformation_enrichment::elasticity
