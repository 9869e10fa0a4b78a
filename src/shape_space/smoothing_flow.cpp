#include "deformation_enrichment/shape_space/smoothing_flow.hpp"

#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <utility>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/connected_components.hpp"
#include "deformation_enrichment/shape_space/path_energy.hpp"
#include "deformation_enrichment/shape_space/rigid_interpolation.hpp"
#include "parallel_for.hpp"

namespace deformation_enrichment::shape_space {
namespace {

int wrap(int i, int count) { return ((i % count) + count) % count; }

// Parallel over shapes only when each shape is big enough (parallel_for.hpp).
bool parallelWorthIt(const std::vector<Eigen::VectorXd>& shapes) {
  return shapes.size() > 1 && shapes.front().size() >= 3 * detail::kParallelVertices;
}

ShapeSequence validated(ShapeSequence input) {
  validateSequence(input, 3);
  return input;
}

FlowOptions checked(FlowOptions options) {
  if (!(options.tau > 0.0 && options.tau <= 1.0)) throw InvalidInputError("flow: tau must lie in (0, 1]");
  if (!(options.rho >= 0.0 && options.rho < 1.0)) throw InvalidInputError("flow: rho must lie in [0, 1)");
  if (options.reduction.subspaceDimension < 1) throw InvalidInputError("flow: subspace dimension must be >= 1");
  if (options.maxTauHalvings < 0) throw InvalidInputError("flow: maxTauHalvings must be >= 0");
  return options;
}

}  // namespace

// The weights, examples and (reduced mode) reference data of shape i's average: eq. 2 + restoring force.
struct SmoothingFlow::AverageProblem {
  std::vector<double> weights;
  std::vector<const Eigen::VectorXd*> examples;
  std::vector<const ReferenceData*> data;  // empty if xData is
};

// The shapes of one trial step and how their averages ended.
struct SmoothingFlow::Trial {
  std::vector<Eigen::VectorXd> shapes;
  std::vector<Eigen::MatrixXd> models;  // each average's final quasi-Newton model (reduced mode)
  int iterations = 0;
  int unconverged = 0;
  double unconvergedGradientNorm = 0.0;
  bool collapsed = false;  // a ghost solve lifted to the fine mesh collapsed a fine triangle: step too long
  ReferenceDataList data;  // the shapes' reference data (evaluation space), if eq. 4 was computed from it
};

SmoothingFlow::SmoothingFlow(const DeformationEnergy& energy, ShapeSequence input, FlowOptions options)
    : energy_(energy),
      input_(validated(std::move(input))),
      options_(checked(std::move(options))),
      space_(energy, input_.triangles, input_.shapes.front(), options_.reduction) {
  pieces_ = mesh::connectedComponents(input_.triangles, input_.numVertices());
  restored_.assign(input_.shapes.size(), options_.restoredShapes.empty() ? 1 : 0);
  for (int i : options_.restoredShapes) {
    if (i < 0 || i >= int(input_.shapes.size()))
      throw InvalidInputError("flow: restored shape index " + std::to_string(i) + " out of range");
    restored_[size_t(i)] = 1;
  }
  setCurrent(input_.shapes);
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
  reduced_.reset();
  if (options_.reduction.reduced) {
    // Preprocess: the subspaces of the sequence, + flow tangents for short sequences.
    std::vector<Eigen::VectorXd> directions;
    if (int(current_.shapes.size()) < options_.flowDirectionShapes) directions = flowTangents(energy_, current_.shapes, options_.closed);
    directions.insert(directions.end(), extraDirections_.begin(), extraDirections_.end());
    reduced_.emplace(space_, current_.shapes, options_.reduction.subspaceDimension, directions);
  }
  std::vector<Eigen::VectorXd> storage, inputStorage;
  const std::vector<Eigen::VectorXd>& origins = space_.restrict(current_.shapes, storage);
  const std::vector<Eigen::VectorXd>& input = space_.restrict(input_.shapes, inputStorage);
  inputData_ = options_.rho > 0.0 ? referenceData(input) : ReferenceDataList{};  // kept for the run
  currentData_ = referenceData(origins);  // also the next step's
  if (reduced_) setWarmStarts(origins, input);
}

void SmoothingFlow::setWarmStarts(const std::vector<Eigen::VectorXd>& origins, const std::vector<Eigen::VectorXd>& input) {
  detail::parallelFor(int(current_.shapes.size()), parallelShapes(), [&](int i) {
    if (!isFree(i)) return;
    // The quasi-Newton model starts at the reduced Hessian of the next step's own objective at its start,
    // not at the rest Hessian of the shape's energy (which ignores the neighbours and their noise):
    // measured on a 140-frame bent sheet with 16 directions, 777 instead of 1191 iterations in the first step
    // at the same preprocess cost (on the 32 noisy MD2 clips with 64: 3449 instead of 3439, no gain).
    const AverageProblem problem = averageProblem(i, options_.tau, origins, input, currentData_);
    const AverageObjective objective(space_.energy(), problem.weights, problem.examples, options_.symmetricAverage, problem.data);
    reduced_->setWarmStart(i, objective.hessian(origins[size_t(i)]));
  });
}

void SmoothingFlow::addDirections(const std::vector<Eigen::VectorXd>& directions) {
  if (!reduced_) return;
  for (const Eigen::VectorXd& d : directions) {
    if (d.size() != current_.shapes.front().size() || !d.allFinite())
      throw InvalidInputError("flow: added subspace direction has the wrong size or is not finite");
    extraDirections_.push_back(d);
  }
  setCurrent(current_.shapes);
}

// The reduced eq. 10 averages aggregate their references (weightedReferences); what the energy computes of
// each reference alone is computed once per shape here instead of once per average.
SmoothingFlow::ReferenceDataList SmoothingFlow::referenceData(const std::vector<Eigen::VectorXd>& shapes) const {
  if (!reduced_ || options_.symmetricAverage) return {};
  ReferenceDataList data(shapes.size());
  detail::parallelFor(int(shapes.size()), parallelShapes(), [&](int i) { data[size_t(i)] = space_.energy().referenceData(shapes[size_t(i)]); });
  return data;
}

bool SmoothingFlow::parallelShapes() const { return options_.parallelShapes && parallelWorthIt(current_.shapes); }

bool SmoothingFlow::isFree(int i) const {
  return options_.closed || (i > 0 && i + 1 < int(current_.shapes.size()));
}

double SmoothingFlow::pathEnergy(const std::vector<Eigen::VectorXd>& shapes) const {
  return shape_space::pathEnergy(energy_, shapes, options_.closed);
}

double SmoothingFlow::controlledPathEnergy(const std::vector<Eigen::VectorXd>& shapes) const {
  std::vector<Eigen::VectorXd> storage;
  return shape_space::pathEnergy(space_.energy(), space_.restrict(shapes, storage), options_.closed);
}

// Eq. 4 of shapes in the evaluation space, from their reference data where the energy can (no pass over the
// shapes: the averages need that data anyway).
double SmoothingFlow::evaluatedPathEnergy(const std::vector<Eigen::VectorXd>& evaluated, const ReferenceDataList& data) const {
  if (!data.empty()) {
    std::vector<const ReferenceData*> pointers;
    for (const auto& d : data) pointers.push_back(d.get());
    if (const std::optional<double> energy = space_.energy().pathEnergy(pointers, options_.closed)) return *energy;
  }
  return shape_space::pathEnergy(space_.energy(), evaluated, options_.closed);
}

std::vector<Eigen::VectorXd> SmoothingFlow::pathGradient() const {
  std::vector<Eigen::VectorXd> gradients;
  shape_space::pathEnergy(energy_, current_.shapes, options_.closed, &gradients, false);
  for (size_t i = 0; i < gradients.size(); ++i)
    if (!isFree(int(i))) gradients[i].setZero();
  return gradients;
}

double SmoothingFlow::reducedPathGradientSquaredNorm() const {
  const std::vector<Eigen::VectorXd> gradients = pathGradient();
  double sum = 0.0;
  for (size_t i = 0; i < gradients.size(); ++i) {
    if (!isFree(int(i))) continue;
    sum += reduced_ ? reduced_->squaredNormInBasis(gradients[i]) : gradients[i].squaredNorm();
  }
  return sum;
}

double SmoothingFlow::reducedResidualSquaredNorm() const {
  return reducedResidualSquaredNorm(current_.shapes);
}

double SmoothingFlow::reducedResidualSquaredNorm(const std::vector<Eigen::VectorXd>& fineShapes) const {
  std::vector<Eigen::VectorXd> storage;
  const std::vector<Eigen::VectorXd>& shapes = space_.restrict(fineShapes, storage);
  const DeformationEnergy& energy = space_.energy();
  const int count = int(shapes.size());
  // Per-shape terms summed in shape order afterwards: the same sum whatever the thread count.
  std::vector<double> terms(shapes.size(), 0.0);
  detail::parallelFor(count, options_.parallelShapes && parallelWorthIt(shapes), [&](int i) {
    if (!isFree(i)) return;
    const Eigen::VectorXd& x = shapes[size_t(i)];
    const Eigen::VectorXd& prev = shapes[size_t(wrap(i - 1, count))];
    const Eigen::VectorXd& next = shapes[size_t(wrap(i + 1, count))];
    Eigen::VectorXd r = energy.gradientDeformed(prev, x) + energy.gradientDeformed(next, x);
    if (options_.symmetricAverage) r += energy.gradientReference(x, prev) + energy.gradientReference(x, next);
    terms[size_t(i)] = reduced_ ? reduced_->squaredNormInEvaluatedBasis(r) : r.squaredNorm();
  });
  double sum = 0.0;
  for (double term : terms) sum += term;
  return sum;
}

Eigen::Index SmoothingFlow::degreesOfFreedom() const {
  Eigen::Index dof = 0;
  for (size_t i = 0; i < current_.shapes.size(); ++i)
    if (isFree(int(i))) dof += reduced_ ? reduced_->dimension() : current_.shapes[i].size();
  return dof;
}

// x and input in the evaluation space; xData: x's reference data (referenceData), or empty.
SmoothingFlow::AverageProblem SmoothingFlow::averageProblem(int i, double tau, const std::vector<Eigen::VectorXd>& x,
                                                            const std::vector<Eigen::VectorXd>& input,
                                                            const ReferenceDataList& xData) const {
  const int count = int(x.size());
  const Eigen::VectorXd& prev = x[size_t(wrap(i - 1, count))];
  const Eigen::VectorXd& succ = x[size_t(wrap(i + 1, count))];
  const DeformationEnergy& energy = space_.energy();
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
  AverageProblem problem{{keep * wPrev, keep * (1.0 - tau), keep * wNext}, {&prev, &x[size_t(i)], &succ}, {}};
  if (!xData.empty())
    problem.data = {xData[size_t(wrap(i - 1, count))].get(), xData[size_t(i)].get(), xData[size_t(wrap(i + 1, count))].get()};
  if (restored_[size_t(i)] && options_.rho > 0.0) {
    problem.weights.push_back(options_.rho);
    problem.examples.push_back(&input[size_t(i)]);
    if (!problem.data.empty()) problem.data.push_back(inputData_.empty() ? nullptr : inputData_[size_t(i)].get());
  }
  return problem;
}

// The average of eq. 2 (+ restoring force) for shape i (arguments as averageProblem's).
AverageResult SmoothingFlow::averageAt(int i, double tau, const std::vector<Eigen::VectorXd>& x,
                                       const std::vector<Eigen::VectorXd>& input, const ReferenceDataList& xData) const {
  const AverageProblem problem = averageProblem(i, tau, x, input, xData);
  if (!reduced_) {
    AverageOptions solverOptions = options_.full;
    solverOptions.symmetric = options_.symmetricAverage;
    return elasticAverage(space_.energy(), problem.weights, problem.examples, x[size_t(i)], solverOptions);
  }
  ReducedAverageOptions solverOptions = options_.reducedSolver;
  solverOptions.symmetric = options_.symmetricAverage;
  return reduced_->average(i, space_, problem.weights, problem.examples, problem.data, x[size_t(i)], solverOptions);
}

// x, input and xData: the current and input shapes in the evaluation space and x's reference data.
SmoothingFlow::Trial SmoothingFlow::trialStep(double tau, const std::vector<Eigen::VectorXd>& x,
                                              const std::vector<Eigen::VectorXd>& input, const ReferenceDataList& xData) const {
  const int count = int(current_.shapes.size());
  // Jacobi: every average uses the previous iterate's neighbours, so the shapes are independent.
  Trial trial;
  trial.shapes.resize(current_.shapes.size());  // the free shapes are filled below: copy only the fixed ones
  trial.models.resize(current_.shapes.size());
  for (int i = 0; i < count; ++i)
    if (!isFree(i)) trial.shapes[size_t(i)] = current_.shapes[size_t(i)];
  detail::parallelFor(count, parallelShapes(), [&](int i) {
    if (!isFree(i)) return;
    AverageResult result = averageAt(i, tau, x, input, xData);
    bool collapsed = false;
    try {  // checked here, while the lifted shape is in this core's cache
      if (space_.ghost()) energy_.checkShape(result.shape);
    } catch (const InvalidInputError&) {
      collapsed = true;
    }
    trial.shapes[size_t(i)] = std::move(result.shape);
    trial.models[size_t(i)] = std::move(result.reducedModel);
#pragma omp critical(de_flow_trial)
    {
      trial.collapsed = trial.collapsed || collapsed;
      trial.iterations += result.iterations;
      if (!result.converged()) {
        ++trial.unconverged;
        trial.unconvergedGradientNorm = std::max(trial.unconvergedGradientNorm, result.gradientNorm);
      }
    }
  });
  return trial;
}

void SmoothingFlow::accept(Trial trial, double controlled) {
  std::vector<Eigen::VectorXd>& shapes = trial.shapes;
  // The energy does not see rigid motions of a shape's connected pieces, so a step leaves their poses to the
  // solver's path (measured on noisy MD2 clips: vertex trajectories up to 2.8x rougher while eq. 4 fell
  // 25x; faerie.md2 has 13 pieces). Every piece is moved back onto its input's pose (Kabsch); eq. 4 and the
  // averages do not change.
  detail::parallelFor(int(shapes.size()), parallelShapes(), [&](int i) {
    if (!isFree(i)) return;
    shapes[size_t(i)] = alignPieces(shapes[size_t(i)], input_.shapes[size_t(i)], pieces_);
    if (reduced_) reduced_->moveTo(i, space_, shapes[size_t(i)], std::move(trial.models[size_t(i)]));
  });
  current_.shapes = std::move(shapes);
  lastControlled_ = controlled;
  currentData_ = std::move(trial.data);  // intrinsic: the same for the pieces moved back
}

FlowStep SmoothingFlow::step() {
  // eq. 10 averaging is not the gradient flow of eq. 4 (only eq. 1 is, Lemma 2), so near its own fixed
  // points eq. 4 may not decrease: there a step is also accepted if it reduces the flow's residual.
  const bool byResidual = options_.acceptResidualDecrease && !options_.symmetricAverage;
  const double residualBefore = byResidual ? reducedResidualSquaredNorm() : 0.0;
  FlowStep fallback;
  Trial fallbackTrial;
  bool haveFallback = false;
  // The same for every trial of this step: each shape is a reference of up to 3 averages in each.
  std::vector<Eigen::VectorXd> storage, inputStorage;
  const std::vector<Eigen::VectorXd>& x = space_.restrict(current_.shapes, storage);
  const std::vector<Eigen::VectorXd>& input = space_.restrict(input_.shapes, inputStorage);
  // The preprocess made the first step's (setCurrent), each accepted step the next one's.
  const ReferenceDataList xData = currentData_.empty() ? referenceData(x) : std::exchange(currentData_, {});
  // The energy after the previous step is the one before this (saves 2 m energy passes per step).
  const double before = lastControlled_ >= 0.0 ? lastControlled_ : evaluatedPathEnergy(x, xData);
  double tau = options_.tau;
  for (int halving = 0; halving <= options_.maxTauHalvings; ++halving, tau *= 0.5) {
    Trial trial = trialStep(tau, x, input, xData);
    double after = std::numeric_limits<double>::infinity();
    try {
      if (!trial.collapsed) {
        std::vector<Eigen::VectorXd> trialStorage;
        const std::vector<Eigen::VectorXd>& evaluated = space_.restrict(trial.shapes, trialStorage);
        trial.data = referenceData(evaluated);
        after = evaluatedPathEnergy(evaluated, trial.data);
      }
    } catch (const InvalidInputError&) {  // a degenerate triangle: the step is too long
    }
    FlowStep report;
    report.pathEnergy = after;
    report.tau = tau;
    report.halvings = halving;
    report.solverIterations = trial.iterations;
    report.unconvergedAverages = trial.unconverged;
    report.unconvergedGradientNorm = trial.unconvergedGradientNorm;
    bool lower = std::isfinite(after) && after < before;
    if (!lower && std::isfinite(after) && byResidual) report.byResidual = lower = reducedResidualSquaredNorm(trial.shapes) < residualBefore;
    if (!lower) continue;
    if (trial.unconverged > 0) {  // try a smaller tau first: its averages start nearer their minimisers
      if (!haveFallback) {
        fallback = report;
        fallbackTrial = std::move(trial);
        haveFallback = true;
      }
      continue;
    }
    accept(std::move(trial), after);
    return report;
  }
  if (haveFallback) {
    accept(std::move(fallbackTrial), fallback.pathEnergy);
    return fallback;
  }
  FlowStep report;
  report.pathEnergy = before;
  report.halvings = options_.maxTauHalvings;
  report.stalled = true;
  return report;
}

}  // namespace deformation_enrichment::shape_space
