#pragma once
// The discrete curve-smoothing flow in shape space ([Brandt16 §4-6]):
//   x_i <- A((1-rho) w_-, x_{i-1}, (1-rho)(1-tau), x_i, (1-rho) w_+, x_{i+1}, rho, input_i)   (eq. 2 + restoring)
// with w_- = w_+ = tau/2 (fixed) or the proportion-preserving weights; open curves keep x_0 and x_m fixed,
// closed curves wrap around. Every shape is updated from the previous iterate (Jacobi, as eq. 2 is
// written), optionally in parallel.
//
// Step control: a step is accepted only if it lowers the path energy (eq. 4; of the ghost shapes if a ghost
// mesh is used), with or without restoring force; otherwise tau is halved. An average that does not
// converge (its last iterate is still a descent point of its objective) also halves tau; if no halving gives
// a step whose averages all converge, the first eq. 4-lowering trial is accepted and its unconverged
// averages are reported. If no tau lowers eq. 4 the step is stalled and the sequence stays: at a geodesic,
// or (with a restoring force) where smoothing and restoring balance. The energy does not see rigid motions
// of a shape's connected pieces, so after every step each piece is moved rigidly (Kabsch) onto its pose in
// the input shape.
#include <memory>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "deformation_enrichment/shape_space/deformation_energy.hpp"
#include "deformation_enrichment/shape_space/elastic_average.hpp"
#include "deformation_enrichment/shape_space/evaluation_space.hpp"
#include "deformation_enrichment/shape_space/reduced_average.hpp"
#include "deformation_enrichment/shape_space/reduced_smoothing_space.hpp"
#include "deformation_enrichment/shape_space/shape_sequence.hpp"

namespace deformation_enrichment::shape_space {

enum class FlowWeights { Fixed, ProportionPreserving };

/// Reduced smoothing's default PCA dimension: every direction of a sequence of up to 65 shapes. A shape can
/// only shed its own noise if the subspace holds it: with 16 directions the six MD2 clips
/// longer than 17 frames kept much of their roughness (fresh noise of 0.1-0.5 %, 10 steps: intrinsic
/// roughness x0.085-0.86, vertex trajectories up to 1.37x rougher, less distortion (edges and volume) than the
/// Gaussian filter at the same roughness on only 4 of 30 runs; with 64: x0.007-0.49, at most x0.97, less
/// distortion on 29 of 30; docs/accuracy.md, Subspace size). The cap bounds each shape's dense d x d quasi-Newton model.
constexpr int kSmoothingSubspaceDimension = 64;

struct FlowOptions {
  FlowOptions() { reduction.subspaceDimension = kSmoothingSubspaceDimension; }

  double tau = 0.5;                  ///< step size in (0, 1]
  bool closed = false;               ///< periodic curve (indices mod m+1); otherwise the ends stay fixed
  FlowWeights weights = FlowWeights::Fixed;
  double rho = 0.0;                  ///< restoring force towards the input, in [0, 1)
  std::vector<int> restoredShapes;   ///< shapes that feel rho; empty = all
  bool symmetricAverage = false;     ///< eq. 1 instead of eq. 10 in every average
  int maxTauHalvings = 12;           ///< step control; after that the step is reported as stalled
  /// eq. 10 averaging is not the gradient flow of eq. 4, so near its own fixed points no tau may lower
  /// eq. 4. If set, such a step is still accepted when it lowers the flow's residual
  /// (reducedResidualSquaredNorm); geodesic() sets it for eq. 10. Off (default): eq. 4 decreases every
  /// accepted step, and the flow reports a stall instead.
  bool acceptResidualDecrease = false;
  /// Reduced mode, subspace size (kSmoothingSubspaceDimension) and ghost mesh ([Brandt16 §6]); full-space
  /// Newton by default.
  ReductionOptions reduction;
  /// Below this many shapes, the flow tangents (eq. 9) of all shapes enrich the shared subspace. [Brandt16 §6]
  /// does this below 20 frames of a coarse curve (geodesic() does); on noisy captures the tangents are
  /// dominated by the floppy bending modes of the noise and mix them into every shape (measured on a
  /// 19-frame sydney.md2 clip with 0.2 % noise, 10 steps: vertex trajectories 1.06x rougher with them,
  /// 0.24x without), so smoothing does not add them by default.
  int flowDirectionShapes = 0;
  /// Solve the shapes' averages in parallel (OpenMP over shapes; meshes of >= 1000 vertices only). Needs
  /// an energy that is safe to call from several threads (DiscreteShells is). Off: the energy parallelises
  /// (but eq. 10 averages with aggregated references, see DeformationEnergy::weightedReferences, run serially).
  bool parallelShapes = false;
  AverageOptions full;
  ReducedAverageOptions reducedSolver;
};

struct FlowStep {
  double pathEnergy = 0.0;  ///< eq. 4 after the step (of the ghost shapes if a ghost mesh is used)
  double tau = 0.0;         ///< step size that was accepted
  int halvings = 0;
  bool stalled = false;     ///< no tau decreased the path energy: the sequence was left unchanged
  bool byResidual = false;  ///< accepted because the residual decreased (acceptResidualDecrease)
  int solverIterations = 0; ///< Newton or quasi-Newton iterations summed over the shapes (accepted trial)
  /// Averages of the accepted trial that did not converge (their last iterates were used), and the largest
  /// gradient norm among them (0 if all converged).
  int unconvergedAverages = 0;
  double unconvergedGradientNorm = 0.0;
  bool converged() const { return !stalled && unconvergedAverages == 0; }
};

class SmoothingFlow {
public:
  /// Validates the input (>= 3 shapes, same sizes, finite, non-degenerate), the options, and in reduced
  /// mode builds the subspaces and warm starts (the preprocess). Throws InvalidInputError.
  SmoothingFlow(const DeformationEnergy& energy, ShapeSequence input, FlowOptions options);

  /// One flow step with step control (see the header comment); never throws for non-convergence.
  FlowStep step();

  const ShapeSequence& current() const { return current_; }
  const FlowOptions& options() const { return options_; }
  /// Eq. 4 on the fine mesh (including the closing segment for closed curves).
  double pathEnergy() const { return pathEnergy(current_.shapes); }
  double pathEnergy(const std::vector<Eigen::VectorXd>& shapes) const;
  /// Left-hand side of eq. 3 per shape (zero vectors for the fixed ends of an open curve).
  std::vector<Eigen::VectorXd> pathGradient() const;
  /// Squared norm of the path gradient projected on each free shape's subspace (full mode: plain norm).
  double reducedPathGradientSquaredNorm() const;
  /// eq. 4 of the ghost shapes (the quantity the step control lowers with a ghost mesh); else pathEnergy().
  double controlledPathEnergy() const { return controlledPathEnergy(current_.shapes); }
  /// Vertices of the ghost mesh in use (0: none).
  Eigen::Index ghostVertices() const { return space_.ghostVertices(); }
  /// Reduced mode: the shared subspace's dimension (at most options' subspaceDimension, fewer if the shapes
  /// span fewer directions); 0 in full mode.
  Eigen::Index subspaceDimension() const { return reduced_ ? reduced_->dimension() : 0; }
  /// Squared norm of the flow's own fixed-point residual, projected like reducedPathGradientSquaredNorm
  /// (on the ghost mesh if one is used):
  /// eq. 3 for the symmetric average (eq. 1); d2 E(x_{i-1}, x_i) + d2 E(x_{i+1}, x_i) for eq. 10, whose
  /// fixed points are the eq. 10-geodesics of [Brandt16 Table 2] (they differ slightly from eq. 3's).
  double reducedResidualSquaredNorm() const;
  double reducedResidualSquaredNorm(const std::vector<Eigen::VectorXd>& shapes) const;
  /// Free degrees of freedom (full: 3V per free shape; reduced: subspace dimensions).
  Eigen::Index degreesOfFreedom() const;
  /// Reduced mode: adds directions (e.g. flow tangents at the current curve) to the shared basis of every
  /// shape and rebuilds the subspaces; they are kept across setCurrent. No effect in full mode.
  void addDirections(const std::vector<Eigen::VectorXd>& directions);
  /// Replaces the current shapes (e.g. after temporal refinement); re-validates, keeps the options.
  void setCurrent(std::vector<Eigen::VectorXd> shapes);

private:
  struct Trial;
  using ReferenceDataList = std::vector<std::shared_ptr<const ReferenceData>>;
  Trial trialStep(double tau, const std::vector<Eigen::VectorXd>& x, const std::vector<Eigen::VectorXd>& input,
                  const ReferenceDataList& xData) const;
  /// Per shape (evaluation space) its reference data for the reduced eq. 10 averages; empty otherwise.
  ReferenceDataList referenceData(const std::vector<Eigen::VectorXd>& shapes) const;
  /// Reduced mode: each free shape's first quasi-Newton model (origins and input in the evaluation space).
  void setWarmStarts(const std::vector<Eigen::VectorXd>& origins, const std::vector<Eigen::VectorXd>& input);
  /// Makes the trial's shapes (with eq. 4 `controlled`) the current ones, each piece moved rigidly onto its
  /// input pose, and its averages' final models the next step's warm starts.
  void accept(Trial trial, double controlled);
  struct AverageProblem;
  AverageProblem averageProblem(int i, double tau, const std::vector<Eigen::VectorXd>& x,
                                const std::vector<Eigen::VectorXd>& input, const ReferenceDataList& xData) const;
  AverageResult averageAt(int i, double tau, const std::vector<Eigen::VectorXd>& x,
                          const std::vector<Eigen::VectorXd>& input, const ReferenceDataList& xData) const;
  double controlledPathEnergy(const std::vector<Eigen::VectorXd>& shapes) const;
  double evaluatedPathEnergy(const std::vector<Eigen::VectorXd>& evaluated, const ReferenceDataList& data) const;
  bool isFree(int i) const;
  bool parallelShapes() const;  ///< loops over shapes on the OpenMP team (options and mesh size)

  const DeformationEnergy& energy_;
  ShapeSequence input_;
  ShapeSequence current_;
  FlowOptions options_;
  EvaluationSpace space_;
  std::vector<char> restored_;
  std::vector<std::vector<int>> pieces_;  ///< connected components of the mesh (each keeps its input pose)
  std::optional<ReducedSmoothingSpace> reduced_;  ///< reduced mode: the shapes' subspaces
  std::vector<Eigen::VectorXd> extraDirections_;  ///< reduced mode: added to the subspaces, kept across setCurrent
  ReferenceDataList inputData_;    ///< the inputs' reference data if a restoring force uses them (referenceData)
  ReferenceDataList currentData_;  ///< current_'s reference data (referenceData) until the next step uses it
  double lastControlled_ = -1.0;  ///< controlledPathEnergy() of current_ after a step (< 0: unknown)
};

}  // namespace deformation_enrichment::shape_space
