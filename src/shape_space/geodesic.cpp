#include "deformation_enrichment/shape_space/geodesic.hpp"

#include <cmath>
#include <memory>
#include <string>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/shape_space/affine_subspace.hpp"
#include "deformation_enrichment/shape_space/elastic_average.hpp"
#include "deformation_enrichment/shape_space/geodesic_path.hpp"
#include "deformation_enrichment/shape_space/path_energy.hpp"
#include "deformation_enrichment/shape_space/rigid_interpolation.hpp"
#include "deformation_enrichment/shape_space/smoothing_flow.hpp"

namespace deformation_enrichment::shape_space {
namespace {

// Resamples the polyline (uniform parameters) at `count` uniform parameters; grid points that coincide
// with old shapes are copied exactly.
std::vector<Eigen::VectorXd> resample(const std::vector<Eigen::VectorXd>& coarse, int count) {
  std::vector<Eigen::VectorXd> fine;
  const int segments = int(coarse.size()) - 1;
  for (int j = 0; j < count; ++j) {
    const double t = double(j) * segments / double(count - 1);
    int k = std::min(int(std::floor(t)), segments - 1);
    double s = t - k;
    if (s < 1e-12) s = 0.0;
    if (s > 1.0 - 1e-12) s = 1.0;
    fine.push_back(rigidAwareInterpolation(coarse[size_t(k)], coarse[size_t(k + 1)], s));
  }
  return fine;
}

// The paper's scheme: the smoothing flow (eq. 2, ends fixed) at every level until its residual meets the rule.
GeodesicResult flowGeodesic(const DeformationEnergy& energy, const Eigen::Matrix3Xi& triangles, const Eigen::VectorXd& a,
                            const Eigen::VectorXd& b, const GeodesicOptions& options) {
  FlowOptions flowOptions;
  flowOptions.tau = options.tau;
  flowOptions.reduction = options.reduction;
  flowOptions.symmetricAverage = options.average.symmetric;
  flowOptions.full = options.average;
  flowOptions.acceptResidualDecrease = true;
  flowOptions.flowDirectionShapes = 20;  // [Brandt16 §6]: coarse curves get their flow tangents  // eq. 10: converge to its own fixed point (see FlowOptions)

  GeodesicResult result;
  std::vector<Eigen::VectorXd> shapes{a, b};
  while (int(shapes.size()) < options.shapes) {
    const int refined = std::min(options.shapes, (int(shapes.size()) - 1) * (options.insertPerSegment + 1) + 1);
    SmoothingFlow flow(energy, ShapeSequence{triangles, resample(shapes, refined)}, flowOptions);
    result.ghostVertices = flow.ghostVertices();
    const double start = flow.reducedResidualSquaredNorm();
    double threshold = std::max(options.absoluteFactor * double(flow.degreesOfFreedom()), options.relativeFactor * start);
    double gradient = start;
    for (int round = 0;; ++round) {
      result.converged = gradient <= threshold;
      for (int it = 0; it < options.maxIterationsPerLevel && !result.converged; ++it) {
        const FlowStep step = flow.step();
        ++result.iterations;
        result.pathEnergyHistory.push_back(flow.ghostVertices() > 0 ? flow.pathEnergy() : step.pathEnergy);
        gradient = flow.reducedResidualSquaredNorm();
        result.converged = gradient <= threshold;
        if (step.stalled) break;  // no tau decreases eq. 4 any more: as converged as this level gets
      }
      if (!flowOptions.reduction.reduced || round == options.enrichmentRounds) break;
      // Check the unprojected residual with the full-space version of the rule.
      FlowOptions fullOptions = flowOptions;
      fullOptions.reduction.reduced = false;
      const SmoothingFlow fullView(energy, flow.current(), fullOptions);
      const double fullResidual = fullView.reducedResidualSquaredNorm();
      const double fullThreshold = std::max(options.absoluteFactor * double(fullView.degreesOfFreedom()),
                                            options.relativeFactor * start);
      if (fullResidual <= fullThreshold) break;
      flow.addDirections(flowTangents(energy, flow.current().shapes, false));
      threshold = std::max(options.absoluteFactor * double(flow.degreesOfFreedom()), options.relativeFactor * start);
      gradient = flow.reducedResidualSquaredNorm();
    }
    result.finalGradientSquaredNorm = gradient;
    {
      FlowOptions fullOptions = flowOptions;
      fullOptions.reduction.reduced = false;
      result.finalFullResidualSquaredNorm = SmoothingFlow(energy, flow.current(), fullOptions).reducedResidualSquaredNorm();
    }
    shapes = flow.current().shapes;
    if (!result.converged && options.requireConvergence)
      throw NumericalError("geodesic: flow on " + std::to_string(refined) + " shapes did not meet the stopping rule (|g|^2 = " +
                           std::to_string(gradient) + " > " + std::to_string(threshold) + ")");
  }
  result.shapes = std::move(shapes);
  return result;
}

// Minimises eq. 4 over all inner shapes at every level (geodesic_path.hpp), reduced or full.
GeodesicResult pathEnergyGeodesic(const DeformationEnergy& energy, const Eigen::Matrix3Xi& triangles,
                                  const Eigen::VectorXd& a, const Eigen::VectorXd& b, const GeodesicOptions& options) {
  const ReductionOptions& reduction = options.reduction;
  PathSolveOptions solveOptions;
  solveOptions.maxIterations = options.maxIterationsPerLevel;
  solveOptions.absoluteFactor = options.absoluteFactor;
  solveOptions.relativeFactor = options.relativeFactor;
  GeodesicResult result;
  // The ghost mesh of the start shape, shared by all levels ([Brandt16 §6]).
  const EvaluationSpace space(energy, triangles, a, reduction);
  result.ghostVertices = space.ghostVertices();
  std::vector<Eigen::VectorXd> shapes{a, b};
  Eigen::MatrixXd carried;  // reduced: the previous level's basis
  // Reduced: eq. 4's gradients and the rest Hessians at the current path, shared by eq. 9's tangents and (on
  // the fine mesh) the solver's start model (measured: a sixth of a finger geodesic); kept across levels so
  // the Hessians reuse their storage.
  std::vector<Eigen::SparseMatrix<double>> rest;
  rest.reserve(size_t(options.shapes));  // growing would copy the matrices
  std::vector<Eigen::VectorXd> gradients;
  while (int(shapes.size()) < options.shapes) {
    const int refined = std::min(options.shapes, (int(shapes.size()) - 1) * (options.insertPerSegment + 1) + 1);
    shapes = resample(shapes, refined);
    PathSolveReport report;
    if (!reduction.reduced) {
      report = minimisePathEnergyFull(energy, shapes, solveOptions);
      result.iterations += report.iterations;
      result.evaluations += report.evaluations;
      result.pathEnergyHistory.push_back(pathEnergy(energy, shapes));
    } else {
      // Subspace: PCA of the level's initial path plus the eq. 9 directions ([Brandt16 §6]: coarse curves get
      // flow directions): at the first level those at the initial path, later the previous level's basis
      // (its tangents were taken at a solved path; new ones would cost a factorisation per shape). Each
      // round adds the tangents at the current path.
      AffineSubspace subspace = pcaSubspace(shapes, reduction.subspaceDimension);
      subspace.origin.setZero();  // only the basis is used: shape k = (its current value) + B q_k
      bool restAtPath = false;
      if (carried.cols() == 0) {
        pathEnergy(energy, shapes, false, &gradients, false);
        restHessians(energy, shapes, rest, !space.ghost());
        restAtPath = true;
        enrich(subspace, flowTangents(gradients, rest, false));
      } else {
        std::vector<Eigen::VectorXd> previous;
        for (Eigen::Index c = 0; c < carried.cols(); ++c) previous.push_back(carried.col(c));
        enrich(subspace, previous);
      }
      for (int round = 0;; ++round) {
        if (!restAtPath && !space.ghost()) restHessians(energy, shapes, rest);  // into the kept storage
        report = minimisePathEnergyReduced(space, shapes, subspace.basis, solveOptions, space.ghost() ? nullptr : &rest);
        restAtPath = false;  // the shapes moved
        result.iterations += report.iterations;
        result.evaluations += report.evaluations;
        result.pathEnergyHistory.push_back(pathEnergy(energy, shapes, false, &gradients, false));
        if (round == options.enrichmentRounds || !report.converged) break;
        if (!space.ghost()) {  // exact energies: stop once the unprojected gradient meets the rule too
          double full = 0.0;
          for (size_t k = 1; k + 1 < gradients.size(); ++k) full += gradients[k].squaredNorm();
          if (full <= options.absoluteFactor * double(a.size()) * double(shapes.size() - 2)) break;
        }
        restHessians(energy, shapes, rest, !space.ghost());  // the ghost's start model needs its own
        restAtPath = true;
        if (enrich(subspace, flowTangents(gradients, rest, false)) == 0) break;
      }
      carried = subspace.basis;
    }
    result.converged = report.converged;
    result.finalGradientSquaredNorm = report.gradientSquaredNorm;
    if (!report.converged && options.requireConvergence)
      throw NumericalError("geodesic: eq. 4 on " + std::to_string(refined) + " shapes did not meet the stopping rule (|g|^2 = " +
                           std::to_string(report.gradientSquaredNorm) + " > " + std::to_string(report.threshold) + ")");
  }
  pathEnergy(energy, shapes, false, &gradients, false);
  result.finalFullResidualSquaredNorm = 0.0;
  for (size_t k = 1; k + 1 < gradients.size(); ++k) result.finalFullResidualSquaredNorm += gradients[k].squaredNorm();
  result.shapes = std::move(shapes);
  return result;
}

}  // namespace

GeodesicResult geodesic(const DeformationEnergy& energy, const Eigen::Matrix3Xi& triangles, const Eigen::VectorXd& a,
                        const Eigen::VectorXd& b, const GeodesicOptions& options) {
  if (options.shapes < 3) throw InvalidInputError("geodesic: needs at least 3 shapes, got " + std::to_string(options.shapes));
  if (options.insertPerSegment < 1) throw InvalidInputError("geodesic: insertPerSegment must be >= 1");
  if (options.enrichmentRounds < 0) throw InvalidInputError("geodesic: enrichmentRounds must be >= 0");
  validateSequence(ShapeSequence{triangles, {a, b}}, 2);
  GeodesicResult result = options.solver == GeodesicSolver::Flow ? flowGeodesic(energy, triangles, a, b, options)
                                                                 : pathEnergyGeodesic(energy, triangles, a, b, options);
  // Reported on the full mesh whatever the solver approximated.
  result.length = pathLength(energy, result.shapes);
  result.pathEnergy = pathEnergy(energy, result.shapes);
  return result;
}

std::vector<Eigen::VectorXd> bezierCurve(const DeformationEnergy& energy, const Eigen::Matrix3Xi& triangles,
                                         const std::vector<Eigen::VectorXd>& controls, int samples,
                                         const GeodesicOptions& options) {
  if (controls.size() < 2) throw InvalidInputError("bezier curve: needs at least 2 control shapes");
  if (samples < 2) throw InvalidInputError("bezier curve: needs at least 2 samples");
  validateSequence(ShapeSequence{triangles, controls}, 2);
  const AverageOptions& averageOptions = options.average;
  // Point at parameter t on a discrete geodesic: grid shape, or the weighted average of the two around t.
  const auto pointOn = [&](const std::vector<Eigen::VectorXd>& path, double t) {
    const int segments = int(path.size()) - 1;
    const double u = t * segments;
    const int k = std::min(int(std::floor(u)), segments - 1);
    const double s = u - k;
    if (s < 1e-12) return path[size_t(k)];
    if (s > 1.0 - 1e-12) return path[size_t(k + 1)];
    const AverageResult average = elasticAverage(energy, {1.0 - s, s}, {&path[size_t(k)], &path[size_t(k + 1)]},
                                                 rigidAwareInterpolation(path[size_t(k)], path[size_t(k + 1)], s),
                                                 averageOptions);
    if (!average.converged() && options.requireConvergence)
      throw NumericalError("bezier curve: the elastic average at t = " + std::to_string(t) + " did not converge (gradient norm " +
                           std::to_string(average.gradientNorm) + ")");
    return average.shape;
  };
  // The geodesics between successive control shapes are shared by all samples: compute them once.
  std::vector<std::vector<Eigen::VectorXd>> firstLevel;
  for (size_t c = 0; c + 1 < controls.size(); ++c)
    firstLevel.push_back(geodesic(energy, triangles, controls[c], controls[c + 1], options).shapes);
  std::vector<Eigen::VectorXd> curve;
  for (int j = 0; j < samples; ++j) {
    const double t = double(j) / double(samples - 1);
    std::vector<Eigen::VectorXd> points;
    for (const auto& path : firstLevel) points.push_back(pointOn(path, t));
    while (points.size() > 1) {  // de Casteljau: replace each pair by the point at t on their geodesic
      std::vector<Eigen::VectorXd> next;
      for (size_t c = 0; c + 1 < points.size(); ++c) {
        if (t == 0.0) next.push_back(points[c]);
        else if (t == 1.0) next.push_back(points[c + 1]);
        else next.push_back(pointOn(geodesic(energy, triangles, points[c], points[c + 1], options).shapes, t));
      }
      points = std::move(next);
    }
    curve.push_back(points.front());
  }
  return curve;
}

}  // namespace deformation_enrichment::shape_space
