#pragma once
// Discrete geodesics between two shapes ([Brandt16 §5-6]): temporal coarse-to-fine refinement. Starting
// from the two end shapes, every level inserts `insertPerSegment` shapes between successive shapes
// (initialised by rigid-aware interpolation) and then either
//  - PathEnergy (default): minimises eq. 4 over all inner shapes at once (geodesic_path.hpp), reduced
//    (Newton over the subspace coordinates, energies on the ghost mesh if the mesh is larger than it) or
//    full (Newton), until the squared norm of the (reduced) gradient of eq. 4 meets the stopping rule; or
//  - Flow: runs the smoothing flow (eq. 2, ends fixed) until its (reduced) residual meets the rule (the
//    paper's own scheme; with eq. 10 averages its limit is an eq. 10-geodesic, not a critical point of eq. 4).
#include <vector>

#include <Eigen/Core>

#include "deformation_enrichment/shape_space/deformation_energy.hpp"
#include "deformation_enrichment/shape_space/path_energy.hpp"
#include "deformation_enrichment/shape_space/elastic_average.hpp"
#include "deformation_enrichment/shape_space/evaluation_space.hpp"

namespace deformation_enrichment::shape_space {

enum class GeodesicSolver { PathEnergy, Flow };

struct GeodesicOptions {
  /// No ghost mesh by default: on the finger it lengthens the geodesic by 3 % for a 1.1x saving (docs/accuracy.md).
  GeodesicOptions() { reduction.useGhostMesh = false; }

  int shapes = 8;              ///< shapes on the final path, ends included (>= 3)
  int insertPerSegment = 2;    ///< paper: two or three
  GeodesicSolver solver = GeodesicSolver::PathEnergy;
  /// Reduced or full space, subspace size and ghost mesh, for both solvers.
  ReductionOptions reduction;
  double tau = 1.0;  ///< Flow only: the flow's step size
  /// The elastic averages: of the Flow solver (symmetric: eq. 1 instead of eq. 10; the Newton settings in
  /// full mode) and of bezierCurve's points between grid shapes.
  AverageOptions average;
  /// Stop a level when the squared gradient norm (PathEnergy: reduced gradient of eq. 4; Flow:
  /// SmoothingFlow::reducedResidualSquaredNorm) <= absoluteFactor * dof (the paper's rule with 1e-8)
  /// or <= relativeFactor * (its value at the start of the level).
  double absoluteFactor = 1e-8;
  double relativeFactor = 1e-10;
  int maxIterationsPerLevel = 1000;  ///< flow steps (Flow) or Newton iterations (PathEnergy)
  /// Reduced mode: after a level meets the rule in its subspace, directions of eq. 9 at the current path
  /// (flow tangents for Flow, pathTangents for PathEnergy) are added to the subspace and the level is
  /// solved again, at most this many times ([Brandt16] uses a Krylov enrichment of [vonTycowicz15] here). Without
  /// a ghost mesh a round is skipped once the unprojected full-space gradient meets the rule.
  int enrichmentRounds = 1;
  bool requireConvergence = true;  ///< throw NumericalError instead of returning an unconverged path
};

struct GeodesicResult {
  std::vector<Eigen::VectorXd> shapes;
  double pathEnergy = 0.0;            ///< eq. 4
  double length = 0.0;                ///< sum_k sqrt((E(x_k, x_k+1) + E(x_k+1, x_k)) / 2)
  /// eq. 4 on the full mesh after every flow step (Flow) or every level and enrichment round (PathEnergy)
  std::vector<double> pathEnergyHistory;
  int iterations = 0;                 ///< flow steps (Flow) or Newton iterations (PathEnergy)
  int evaluations = 0;                ///< PathEnergy: evaluations of eq. 4 with gradient (2K energy passes each)
  Eigen::Index ghostVertices = 0;     ///< vertices of the ghost mesh used (0: none)
  bool converged = false;
  double finalGradientSquaredNorm = 0.0;      ///< the stopping rule's residual (reduced / ghost in those modes)
  double finalFullResidualSquaredNorm = 0.0;  ///< the same residual unprojected
};

/// Geodesic from a to b over the shared topology `triangles`. Throws InvalidInputError for bad input
/// (sizes, NaN, degenerate triangles, fewer than 3 shapes requested) and NumericalError on failure.
GeodesicResult geodesic(const DeformationEnergy& energy, const Eigen::Matrix3Xi& triangles, const Eigen::VectorXd& a,
                        const Eigen::VectorXd& b, const GeodesicOptions& options = {});

/// De Casteljau's algorithm in shape space ([Brandt16 §7]): straight lines become geodesics. Each
/// geodesic is computed with `options.shapes` shapes; the point at parameter t between grid shapes
/// x_k, x_k+1 is the elastic average A(1 - s, x_k, s, x_k+1) (exact on the grid). Returns `samples`
/// shapes for t = 0 .. 1 (the first and last equal the first and last control shape).
std::vector<Eigen::VectorXd> bezierCurve(const DeformationEnergy& energy, const Eigen::Matrix3Xi& triangles,
                                         const std::vector<Eigen::VectorXd>& controls, int samples,
                                         const GeodesicOptions& options = {});

}  // namespace deformation_enrichment::shape_space
