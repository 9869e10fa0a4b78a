#include "deformation_enrichment/shape_space/geodesic.hpp"

#include <cmath>
#include <string>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/shape_space/elastic_average.hpp"
#include "deformation_enrichment/shape_space/rigid_interpolation.hpp"

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

}  // namespace

double pathLength(const DeformationEnergy& energy, const std::vector<Eigen::VectorXd>& shapes) {
  double length = 0.0;
  for (size_t k = 0; k + 1 < shapes.size(); ++k)
    length += std::sqrt(std::max(0.5 * (energy.value(shapes[k], shapes[k + 1]) + energy.value(shapes[k + 1], shapes[k])), 0.0));
  return length;
}

GeodesicResult geodesic(const DeformationEnergy& energy, const Eigen::Matrix3Xi& triangles, const Eigen::VectorXd& a,
                        const Eigen::VectorXd& b, const GeodesicOptions& options) {
  if (options.shapes < 3) throw InvalidInputError("geodesic: needs at least 3 shapes, got " + std::to_string(options.shapes));
  if (options.insertPerSegment < 1) throw InvalidInputError("geodesic: insertPerSegment must be >= 1");
  validateSequence(ShapeSequence{triangles, {a, b}}, 2);
  FlowOptions flowOptions = options.flow;
  flowOptions.closed = false;
  flowOptions.rho = 0.0;
  flowOptions.acceptResidualDecrease = true;  // eq. 10: converge to its own fixed point (see FlowOptions)

  GeodesicResult result;
  std::vector<Eigen::VectorXd> shapes{a, b};
  while (int(shapes.size()) < options.shapes) {
    const int refined = std::min(options.shapes, (int(shapes.size()) - 1) * (options.insertPerSegment + 1) + 1);
    SmoothingFlow flow(energy, ShapeSequence{triangles, resample(shapes, refined)}, flowOptions);
    const double start = flow.reducedResidualSquaredNorm();
    double threshold = std::max(options.absoluteFactor * double(flow.degreesOfFreedom()), options.relativeFactor * start);
    double gradient = start;
    for (int round = 0;; ++round) {
      result.converged = gradient <= threshold;
      for (int it = 0; it < options.maxIterationsPerLevel && !result.converged; ++it) {
        const FlowStep step = flow.step();
        ++result.iterations;
        result.pathEnergyHistory.push_back(step.pathEnergy);
        gradient = flow.reducedResidualSquaredNorm();
        result.converged = gradient <= threshold;
        if (step.stalled) break;  // no tau decreases eq. 4 any more: as converged as this level gets
      }
      if (!flowOptions.reduced || round == options.enrichmentRounds) break;
      // Check the unprojected residual with the full-space version of the rule.
      FlowOptions fullOptions = flowOptions;
      fullOptions.reduced = false;
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
      fullOptions.reduced = false;
      result.finalFullResidualSquaredNorm = SmoothingFlow(energy, flow.current(), fullOptions).reducedResidualSquaredNorm();
    }
    shapes = flow.current().shapes;
    if (!result.converged && options.requireConvergence)
      throw NumericalError("geodesic: flow on " + std::to_string(refined) + " shapes did not meet the stopping rule (|g|^2 = " +
                           std::to_string(gradient) + " > " + std::to_string(threshold) + ")");
  }
  result.shapes = std::move(shapes);
  result.length = pathLength(energy, result.shapes);
  result.pathEnergy = 0.0;
  for (size_t k = 0; k + 1 < result.shapes.size(); ++k)
    result.pathEnergy += energy.value(result.shapes[k], result.shapes[k + 1]) + energy.value(result.shapes[k + 1], result.shapes[k]);
  return result;
}

std::vector<Eigen::VectorXd> bezierCurve(const DeformationEnergy& energy, const Eigen::Matrix3Xi& triangles,
                                         const std::vector<Eigen::VectorXd>& controls, int samples,
                                         const GeodesicOptions& options) {
  if (controls.size() < 2) throw InvalidInputError("bezier curve: needs at least 2 control shapes");
  if (samples < 2) throw InvalidInputError("bezier curve: needs at least 2 samples");
  validateSequence(ShapeSequence{triangles, controls}, 2);
  AverageOptions averageOptions = options.flow.full;
  averageOptions.symmetric = options.flow.symmetricAverage;
  // Point at parameter t on a discrete geodesic: grid shape, or the weighted average of the two around t.
  const auto pointOn = [&](const std::vector<Eigen::VectorXd>& path, double t) {
    const int segments = int(path.size()) - 1;
    const double u = t * segments;
    const int k = std::min(int(std::floor(u)), segments - 1);
    const double s = u - k;
    if (s < 1e-12) return path[size_t(k)];
    if (s > 1.0 - 1e-12) return path[size_t(k + 1)];
    return elasticAverage(energy, {1.0 - s, s}, {&path[size_t(k)], &path[size_t(k + 1)]},
                          rigidAwareInterpolation(path[size_t(k)], path[size_t(k + 1)], s), averageOptions)
        .shape;
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
