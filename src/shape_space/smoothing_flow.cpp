#include "deformation_enrichment/shape_space/smoothing_flow.hpp"

#include <cmath>
#include <exception>
#include <memory>
#include <string>

#include <Eigen/SparseCholesky>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/shape_space/affine_subspace.hpp"

namespace deformation_enrichment::shape_space {
namespace {

int wrap(int i, int count) { return ((i % count) + count) % count; }

// Parallel over shapes only when each shape is big enough: on small meshes the OpenMP team's idle
// spinning costs more than the work (measured 5x slower on a loaded 2-core machine).
bool parallelWorthIt(const std::vector<Eigen::VectorXd>& shapes) {
  return shapes.size() > 1 && shapes.front().size() >= 3000;
}

}  // namespace

Eigen::VectorXd pathGradientAt(const DeformationEnergy& energy, const Eigen::VectorXd& x, const Eigen::VectorXd* prev,
                               const Eigen::VectorXd* next) {
  Eigen::VectorXd g = Eigen::VectorXd::Zero(x.size());
  // eq. 3: d1 E(x_i, x_{i-1}) + d2 E(x_{i-1}, x_i) + d1 E(x_i, x_{i+1}) + d2 E(x_{i+1}, x_i)
  for (const Eigen::VectorXd* neighbour : {prev, next}) {
    if (!neighbour) continue;
    g += energy.gradientReference(x, *neighbour);
    g += energy.gradientDeformed(*neighbour, x);
  }
  return g;
}

std::vector<Eigen::VectorXd> flowTangents(const DeformationEnergy& energy, const std::vector<Eigen::VectorXd>& shapes,
                                          bool closed) {
  const int count = int(shapes.size());
  std::vector<Eigen::VectorXd> tangents(shapes.size());
  for (int i = 0; i < count; ++i) {
    tangents[size_t(i)] = Eigen::VectorXd::Zero(shapes[size_t(i)].size());
    if (!closed && (i == 0 || i == count - 1)) continue;
    const Eigen::VectorXd& x = shapes[size_t(i)];
    const Eigen::VectorXd g = pathGradientAt(energy, x, &shapes[size_t(wrap(i - 1, count))],
                                             &shapes[size_t(wrap(i + 1, count))]);
    // eq. 9: (d1d1 E(x,x) + d2d2 E(x,x)) dx/dtau = -1/2 (eq. 3 LHS); a ridge removes the rigid null space.
    // d1d1 E(x,x) = d2d2 E(x,x) (E(x,x) = 0 with vanishing gradients for every x), so one d2d2 pass.
    Eigen::SparseMatrix<double> h = 2.0 * energy.hessianDeformed(x, x);
    const double ridge = 1e-8 * std::max(h.diagonal().cwiseAbs().mean(), 1e-300);
    for (Eigen::Index k = 0; k < h.rows(); ++k) h.coeffRef(k, k) += ridge;
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(h);
    if (solver.info() != Eigen::Success) throw NumericalError("flow tangent: rest Hessian factorisation failed");
    tangents[size_t(i)] = -0.5 * solver.solve(g);
  }
  return tangents;
}

SmoothingFlow::SmoothingFlow(const DeformationEnergy& energy, ShapeSequence input, FlowOptions options)
    : energy_(energy), input_(std::move(input)), options_(std::move(options)) {
  validateSequence(input_, 3);
  if (!(options_.tau > 0.0 && options_.tau <= 1.0)) throw InvalidInputError("flow: tau must lie in (0, 1]");
  if (!(options_.rho >= 0.0 && options_.rho < 1.0)) throw InvalidInputError("flow: rho must lie in [0, 1)");
  if (options_.subspaceDimension < 1) throw InvalidInputError("flow: subspace dimension must be >= 1");
  restored_.assign(input_.shapes.size(), options_.restoredShapes.empty() ? 1 : 0);
  for (int i : options_.restoredShapes) {
    if (i < 0 || i >= int(input_.shapes.size()))
      throw InvalidInputError("flow: restored shape index " + std::to_string(i) + " out of range");
    restored_[size_t(i)] = 1;
  }
  current_ = input_;
  if (options_.reduced && options_.useGhostMesh && input_.numVertices() > options_.ghostMesh.targetVertices) {
    ghost_ = std::make_unique<GhostMesh>(ghostMesh(input_.triangles, input_.shapes.front(), options_.ghostMesh));
    ghostEnergy_ = energy_.onTriangles(ghost_->triangles, ghost_->numVertices());
  }
  setCurrent(current_.shapes);
}

std::vector<Eigen::VectorXd> SmoothingFlow::evaluatedShapes(const std::vector<Eigen::VectorXd>& shapes) const {
  if (!ghost_) return shapes;
  std::vector<Eigen::VectorXd> out;
  out.reserve(shapes.size());
  for (const Eigen::VectorXd& x : shapes) out.push_back(ghost_->restrict(x));
  return out;
}

void SmoothingFlow::setCurrent(std::vector<Eigen::VectorXd> shapes) {
  ShapeSequence next{input_.triangles, std::move(shapes)};
  validateSequence(next, 3);
  if (next.numVertices() != input_.numVertices())
    throw InvalidInputError("flow: replacement shapes have a different vertex count");
  if (next.shapes.size() != input_.shapes.size()) {
    // Temporal refinement: the new shapes become the reference of the restoring force.
    input_.shapes = next.shapes;
    restored_.assign(input_.shapes.size(), options_.restoredShapes.empty() ? 1 : 0);
  }
  current_ = std::move(next);
  lastControlled_ = -1.0;
  spaces_.clear();
  fineBasis_.reset();
  fineOrigins_.clear();
  if (!options_.reduced) return;
  // Preprocess: PCA of the sequence, + flow tangents for short sequences; each shape's affine space passes
  // through the shape itself, so the current shape is exactly representable.
  AffineSubspace pca = pcaSubspace(current_.shapes, options_.subspaceDimension);
  if (int(current_.shapes.size()) < options_.flowDirectionShapes)
    enrich(pca, flowTangents(energy_, current_.shapes, options_.closed));
  enrich(pca, extraDirections_);
  if (pca.dimension() == 0) throw InvalidInputError("flow: the shapes span no subspace (all identical?)");
  fineBasis_ = std::make_shared<const Eigen::MatrixXd>(std::move(pca.basis));
  fineOrigins_ = current_.shapes;
  // With a ghost mesh the reduced spaces (and preconditioners) live on it: origin S x_i, basis S B.
  const auto basis = ghost_ ? std::make_shared<const Eigen::MatrixXd>(ghost_->restrictRows(*fineBasis_)) : fineBasis_;
  const std::vector<Eigen::VectorXd> origins = evaluatedShapes(current_.shapes);
  const DeformationEnergy& energy = evaluated();
  spaces_.resize(current_.shapes.size());
  std::exception_ptr error;
#pragma omp parallel for schedule(dynamic) if (options_.parallelShapes && parallelWorthIt(current_.shapes))
  for (int i = 0; i < int(current_.shapes.size()); ++i) {
    if (!isFree(i)) continue;
    try {
      spaces_[size_t(i)] = makeReducedSpace(energy, origins[size_t(i)], basis, origins[size_t(i)]);
    } catch (...) {
#pragma omp critical
      error = std::current_exception();
    }
  }
  if (error) std::rethrow_exception(error);
}

void SmoothingFlow::addDirections(const std::vector<Eigen::VectorXd>& directions) {
  if (!options_.reduced) return;
  for (const Eigen::VectorXd& d : directions) {
    if (d.size() != current_.shapes.front().size() || !d.allFinite())
      throw InvalidInputError("flow: added subspace direction has the wrong size or is not finite");
    extraDirections_.push_back(d);
  }
  setCurrent(current_.shapes);
}

bool SmoothingFlow::isFree(int i) const {
  return options_.closed || (i > 0 && i + 1 < int(current_.shapes.size()));
}

double SmoothingFlow::pathEnergy(const std::vector<Eigen::VectorXd>& shapes) const {
  const int count = int(shapes.size());
  const int segments = options_.closed ? count : count - 1;
  double sum = 0.0;
#pragma omp parallel for reduction(+ : sum) if (options_.parallelShapes && parallelWorthIt(shapes))
  for (int k = 0; k < segments; ++k) {  // eq. 4
    const Eigen::VectorXd& a = shapes[size_t(k)];
    const Eigen::VectorXd& b = shapes[size_t(wrap(k + 1, count))];
    sum += energy_.value(a, b) + energy_.value(b, a);
  }
  return sum;
}

double SmoothingFlow::controlledPathEnergy(const std::vector<Eigen::VectorXd>& shapes) const {
  if (!ghost_) return pathEnergy(shapes);
  const std::vector<Eigen::VectorXd> coarse = evaluatedShapes(shapes);
  const int count = int(coarse.size());
  const int segments = options_.closed ? count : count - 1;
  double sum = 0.0;
#pragma omp parallel for reduction(+ : sum) if (options_.parallelShapes)
  for (int k = 0; k < segments; ++k) {  // eq. 4 on the ghost mesh
    const Eigen::VectorXd& a = coarse[size_t(k)];
    const Eigen::VectorXd& b = coarse[size_t(wrap(k + 1, count))];
    sum += ghostEnergy_->value(a, b) + ghostEnergy_->value(b, a);
  }
  return sum;
}

std::vector<Eigen::VectorXd> SmoothingFlow::pathGradient() const {
  const int count = int(current_.shapes.size());
  std::vector<Eigen::VectorXd> gradients(current_.shapes.size());
#pragma omp parallel for if (options_.parallelShapes && parallelWorthIt(current_.shapes))
  for (int i = 0; i < count; ++i) {
    if (!isFree(i)) {
      gradients[size_t(i)] = Eigen::VectorXd::Zero(current_.shapes[size_t(i)].size());
      continue;
    }
    gradients[size_t(i)] = pathGradientAt(energy_, current_.shapes[size_t(i)], &current_.shapes[size_t(wrap(i - 1, count))],
                                          &current_.shapes[size_t(wrap(i + 1, count))]);
  }
  return gradients;
}

double SmoothingFlow::reducedPathGradientSquaredNorm() const {
  const std::vector<Eigen::VectorXd> gradients = pathGradient();
  double sum = 0.0;
  for (size_t i = 0; i < gradients.size(); ++i) {
    if (!isFree(int(i))) continue;
    sum += options_.reduced ? (fineBasis_->transpose() * gradients[i]).squaredNorm() : gradients[i].squaredNorm();
  }
  return sum;
}

double SmoothingFlow::reducedResidualSquaredNorm() const {
  return reducedResidualSquaredNorm(current_.shapes);
}

double SmoothingFlow::reducedResidualSquaredNorm(const std::vector<Eigen::VectorXd>& fineShapes) const {
  std::vector<Eigen::VectorXd> coarse;
  if (ghost_) coarse = evaluatedShapes(fineShapes);
  const std::vector<Eigen::VectorXd>& shapes = ghost_ ? coarse : fineShapes;
  const DeformationEnergy& energy = evaluated();
  const int count = int(shapes.size());
  double sum = 0.0;
#pragma omp parallel for reduction(+ : sum) if (options_.parallelShapes && parallelWorthIt(shapes))
  for (int i = 0; i < count; ++i) {
    if (!isFree(i)) continue;
    const Eigen::VectorXd& x = shapes[size_t(i)];
    const Eigen::VectorXd& prev = shapes[size_t(wrap(i - 1, count))];
    const Eigen::VectorXd& next = shapes[size_t(wrap(i + 1, count))];
    Eigen::VectorXd r = energy.gradientDeformed(prev, x) + energy.gradientDeformed(next, x);
    if (options_.symmetricAverage) r += energy.gradientReference(x, prev) + energy.gradientReference(x, next);
    sum += options_.reduced ? (spaces_[size_t(i)].basis->transpose() * r).squaredNorm() : r.squaredNorm();
  }
  return sum;
}

Eigen::Index SmoothingFlow::degreesOfFreedom() const {
  Eigen::Index dof = 0;
  for (size_t i = 0; i < current_.shapes.size(); ++i)
    if (isFree(int(i))) dof += options_.reduced ? spaces_[i].basis->cols() : current_.shapes[i].size();
  return dof;
}

std::vector<Eigen::VectorXd> SmoothingFlow::trialStep(double tau, int* iterations) const {
  const int count = int(current_.shapes.size());
  // Jacobi: every average uses the previous iterate's neighbours, so the shapes are independent.
  std::vector<Eigen::VectorXd> coarse, coarseInput;  // ghost shapes (no copies without a ghost mesh)
  if (ghost_) {
    coarse = evaluatedShapes(current_.shapes);
    coarseInput = evaluatedShapes(input_.shapes);
  }
  const std::vector<Eigen::VectorXd>& x = ghost_ ? coarse : current_.shapes;
  const std::vector<Eigen::VectorXd>& input = ghost_ ? coarseInput : input_.shapes;
  const DeformationEnergy& energy = evaluated();
  std::vector<Eigen::VectorXd> next = current_.shapes;
  std::exception_ptr error;
  int totalIterations = 0;
#pragma omp parallel for schedule(dynamic) if (options_.parallelShapes && parallelWorthIt(current_.shapes))
  for (int i = 0; i < count; ++i) {
    if (!isFree(i) || error) continue;
    try {
      const Eigen::VectorXd& prev = x[size_t(wrap(i - 1, count))];
      const Eigen::VectorXd& succ = x[size_t(wrap(i + 1, count))];
      double wPrev = 0.5 * tau, wNext = 0.5 * tau;
      if (options_.weights == FlowWeights::ProportionPreserving) {
        // l_{i-1} = sqrt(E(x_{i-1}, x_i)), l_i = sqrt(E(x_i, x_{i+1})); the nearer neighbour pulls harder so
        // that on a straight path the current ratio l_{i-1} : l_i is stationary (it is preserved).
        const double lPrev = std::sqrt(std::max(energy.value(prev, x[size_t(i)]), 0.0));
        const double lNext = std::sqrt(std::max(energy.value(x[size_t(i)], succ), 0.0));
        if (lPrev + lNext > 0.0) {
          wPrev = tau * lNext / (lPrev + lNext);
          wNext = tau * lPrev / (lPrev + lNext);
        }
      }
      const double keep = restored_[size_t(i)] ? 1.0 - options_.rho : 1.0;
      std::vector<double> weights{keep * wPrev, keep * (1.0 - tau), keep * wNext};
      std::vector<const Eigen::VectorXd*> examples{&prev, &x[size_t(i)], &succ};
      if (restored_[size_t(i)] && options_.rho > 0.0) {
        weights.push_back(options_.rho);
        examples.push_back(&input[size_t(i)]);
      }
      AverageResult result;
      if (options_.reduced) {
        ReducedAverageOptions solverOptions = options_.reducedSolver;
        solverOptions.symmetric = options_.symmetricAverage;
        result = reducedElasticAverage(energy, weights, examples, spaces_[size_t(i)], x[size_t(i)], solverOptions);
        // Same reduced coordinates on the fine mesh (exact lift without a ghost mesh).
        if (ghost_) result.shape = fineOrigins_[size_t(i)] + *fineBasis_ * result.reducedCoordinates;
      } else {
        AverageOptions solverOptions = options_.full;
        solverOptions.symmetric = options_.symmetricAverage;
        result = elasticAverage(energy, weights, examples, x[size_t(i)], solverOptions);
      }
      next[size_t(i)] = std::move(result.shape);
#pragma omp atomic
      totalIterations += result.iterations;
    } catch (...) {
#pragma omp critical
      error = std::current_exception();
    }
  }
  if (error) std::rethrow_exception(error);
  if (iterations) *iterations = totalIterations;
  return next;
}

FlowStep SmoothingFlow::step() {
  FlowStep report;
  // The energy after the previous step is the one before this (saves 2 m energy passes per step).
  const double before = lastControlled_ >= 0.0 ? lastControlled_ : controlledPathEnergy();
  // eq. 10 averaging is not the gradient flow of eq. 4 (only eq. 1 is, Lemma 2), so near its own fixed
  // points eq. 4 may not decrease: there a step is also accepted if it reduces the flow's residual.
  const bool byResidual = options_.acceptResidualDecrease && !options_.symmetricAverage;
  const double residualBefore = byResidual ? reducedResidualSquaredNorm() : 0.0;
  double tau = options_.tau;
  for (int halving = 0; halving <= options_.maxTauHalvings; ++halving, tau *= 0.5) {
    int iterations = 0;
    std::vector<Eigen::VectorXd> next = trialStep(tau, &iterations);
    const double after = controlledPathEnergy(next);
    // With a restoring force the flow trades path energy against fidelity, so only rho = 0 is controlled.
    bool accept = std::isfinite(after) && (after < before || options_.rho > 0.0);
    if (!accept && std::isfinite(after) && byResidual) {
      accept = reducedResidualSquaredNorm(next) < residualBefore;
      report.byResidual = accept;
    }
    report.solverIterations = iterations;
    if (accept) {
      current_.shapes = std::move(next);
      lastControlled_ = after;
      report.pathEnergy = after;
      report.tau = tau;
      report.halvings = halving;
      return report;
    }
  }
  report.pathEnergy = before;
  report.tau = 0.0;
  report.halvings = options_.maxTauHalvings;
  report.stalled = true;
  return report;
}

}  // namespace deformation_enrichment::shape_space
