#pragma once
// Discrete geodesics between two shapes (paper 004 §5-6): temporal coarse-to-fine refinement. Starting
// from the two end shapes, every level inserts `insertPerSegment` shapes between successive shapes
// (initialised by rigid-aware interpolation) and runs the smoothing flow (eq. 2, ends fixed) until the
// squared norm of the (reduced) gradient of eq. 4 falls below the stopping rule.
#include <vector>

#include <Eigen/Core>

#include "deformation_enrichment/shape_space/deformation_energy.hpp"
#include "deformation_enrichment/shape_space/smoothing_flow.hpp"

namespace deformation_enrichment::shape_space {

struct GeodesicOptions {
  int shapes = 8;              ///< shapes on the final path, ends included (>= 3)
  int insertPerSegment = 2;    ///< paper: two or three
  FlowOptions flow;            ///< tau, reduced/full, subspace size, symmetric averaging (closed is ignored)
  /// Stop a level when |reduced residual|^2 (SmoothingFlow::reducedResidualSquaredNorm: the gradient of
  /// eq. 4 with symmetric averaging) <= absoluteFactor * dof (the paper's rule with 1e-8)
  /// or <= relativeFactor * (its value at the start of the level).
  double absoluteFactor = 1e-8;
  double relativeFactor = 1e-10;
  int maxIterationsPerLevel = 1000;
  /// Reduced mode: after a level meets the rule in its subspace, the full-space residual is checked; if it
  /// fails the rule, the flow tangents (eq. 9) of the current curve are added to the subspace and the flow
  /// continues, at most this many times per level (paper 004 uses a Krylov enrichment of [vTSSH15] here).
  int enrichmentRounds = 4;
  bool requireConvergence = true;  ///< throw NumericalError instead of returning an unconverged path
};

struct GeodesicResult {
  std::vector<Eigen::VectorXd> shapes;
  double pathEnergy = 0.0;            ///< eq. 4
  double length = 0.0;                ///< sum_k sqrt((E(x_k, x_k+1) + E(x_k+1, x_k)) / 2)
  std::vector<double> pathEnergyHistory;  ///< after every flow step, all levels
  int iterations = 0;
  bool converged = false;
  double finalGradientSquaredNorm = 0.0;      ///< the stopping rule's residual (reduced in reduced mode)
  double finalFullResidualSquaredNorm = 0.0;  ///< the same residual unprojected
};

/// Geodesic from a to b over the shared topology `triangles`. Throws InvalidInputError for bad input
/// (sizes, NaN, degenerate triangles, fewer than 3 shapes requested) and NumericalError on failure.
GeodesicResult geodesic(const DeformationEnergy& energy, const Eigen::Matrix3Xi& triangles, const Eigen::VectorXd& a,
                        const Eigen::VectorXd& b, const GeodesicOptions& options = {});

/// Length of a path as defined for GeodesicResult::length.
double pathLength(const DeformationEnergy& energy, const std::vector<Eigen::VectorXd>& shapes);

/// De Casteljau's algorithm in shape space (paper 004 §7): straight lines become geodesics. Each
/// geodesic is computed with `options.shapes` shapes; the point at parameter t between grid shapes
/// x_k, x_k+1 is the elastic average A(1 - s, x_k, s, x_k+1) (exact on the grid). Returns `samples`
/// shapes for t = 0 .. 1 (the first and last equal the first and last control shape).
std::vector<Eigen::VectorXd> bezierCurve(const DeformationEnergy& energy, const Eigen::Matrix3Xi& triangles,
                                         const std::vector<Eigen::VectorXd>& controls, int samples,
                                         const GeodesicOptions& options = {});

}  // namespace deformation_enrichment::shape_space
