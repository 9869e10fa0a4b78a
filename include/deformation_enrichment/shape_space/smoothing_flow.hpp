#pragma once
// The discrete curve-smoothing flow in shape space ([Brandt16 §4-6]):
//   x_i <- A((1-rho) w_-, x_{i-1}, (1-rho)(1-tau), x_i, (1-rho) w_+, x_{i+1}, rho, input_i)   (eq. 2 + restoring)
// with w_- = w_+ = tau/2 (fixed) or the proportion-preserving weights; open curves keep x_0 and x_m fixed,
// closed curves wrap around. Every shape is updated from the previous iterate (Jacobi, as eq. 2 is
// written), optionally in parallel. Step control: tau is halved until the path energy (eq. 4) decreases.
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "deformation_enrichment/shape_space/deformation_energy.hpp"
#include "deformation_enrichment/shape_space/elastic_average.hpp"
#include "deformation_enrichment/shape_space/ghost_mesh.hpp"
#include "deformation_enrichment/shape_space/reduced_average.hpp"
#include "deformation_enrichment/shape_space/shape_sequence.hpp"

namespace deformation_enrichment::shape_space {

enum class FlowWeights { Fixed, ProportionPreserving };

struct FlowOptions {
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
  bool reduced = false;              ///< reduced (subspace + L-BFGS) instead of full-space Newton
  int subspaceDimension = 16;        ///< PCA directions of the sequence (reduced mode)
  int flowDirectionShapes = 20;      ///< below this many shapes, flow tangents enrich the subspace (paper: 20)
  /// Reduced mode: approximate the reduced energies and gradients on a ghost mesh ([Brandt16 §6]) of the
  /// first shape when the mesh has more than ghostMesh.targetVertices vertices. The averages, the step
  /// control and the residuals then use the ghost energy; the shapes stay fine (same reduced coordinates).
  bool useGhostMesh = true;
  GhostMeshOptions ghostMesh;
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
  int solverIterations = 0; ///< Newton or L-BFGS iterations summed over the shapes (accepted trial)
};

class SmoothingFlow {
public:
  /// Validates the input (>= 3 shapes, same sizes, finite, non-degenerate), the options, and in reduced
  /// mode builds the subspaces and preconditioners (the preprocess). Throws InvalidInputError.
  SmoothingFlow(const DeformationEnergy& energy, ShapeSequence input, FlowOptions options);

  /// One flow step with step control. Throws NumericalError if an average fails to converge.
  FlowStep step();

  const ShapeSequence& current() const { return current_; }
  const FlowOptions& options() const { return options_; }
  double pathEnergy() const { return pathEnergy(current_.shapes); }
  /// Eq. 4 (including the closing segment for closed curves).
  double pathEnergy(const std::vector<Eigen::VectorXd>& shapes) const;
  /// Left-hand side of eq. 3 per shape (zero vectors for the fixed ends of an open curve).
  std::vector<Eigen::VectorXd> pathGradient() const;
  /// Squared norm of the path gradient projected on each free shape's subspace (full mode: plain norm).
  double reducedPathGradientSquaredNorm() const;
  /// eq. 4 of the ghost shapes (the quantity the step control lowers with a ghost mesh); else pathEnergy().
  double controlledPathEnergy() const { return controlledPathEnergy(current_.shapes); }
  /// Vertices of the ghost mesh in use (0: none).
  Eigen::Index ghostVertices() const { return ghost_ ? ghost_->numVertices() : 0; }
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
  std::vector<Eigen::VectorXd> trialStep(double tau, int* iterations) const;
  double controlledPathEnergy(const std::vector<Eigen::VectorXd>& shapes) const;
  /// The energy and shapes the averages work on: the ghost's, or the fine ones.
  const DeformationEnergy& evaluated() const { return ghostEnergy_ ? *ghostEnergy_ : energy_; }
  std::vector<Eigen::VectorXd> evaluatedShapes(const std::vector<Eigen::VectorXd>& shapes) const;
  bool isFree(int i) const;

  const DeformationEnergy& energy_;
  ShapeSequence input_;
  ShapeSequence current_;
  FlowOptions options_;
  std::vector<char> restored_;
  std::vector<ReducedSpace> spaces_;  ///< per shape (reduced mode), on the ghost mesh if one is used
  std::shared_ptr<const Eigen::MatrixXd> fineBasis_;  ///< reduced mode: the shared basis on the fine mesh
  std::vector<Eigen::VectorXd> fineOrigins_;          ///< reduced mode: shape i = fineOrigins_[i] + B q
  double lastControlled_ = -1.0;  ///< controlledPathEnergy() of current_ after a step (< 0: unknown)
  std::unique_ptr<GhostMesh> ghost_;
  std::unique_ptr<DeformationEnergy> ghostEnergy_;
  std::vector<Eigen::VectorXd> extraDirections_;
};

/// Flow tangent of eq. 9 for every free shape: (d1d1 E(x,x) + d2d2 E(x,x)) v = 1/2 (eq. 3 LHS); zero
/// vectors for fixed ends. Used to enrich subspaces of short sequences.
std::vector<Eigen::VectorXd> flowTangents(const DeformationEnergy& energy, const std::vector<Eigen::VectorXd>& shapes,
                                          bool closed);

/// Eq. 3 LHS for shape i given its neighbours (either may be null at an open end).
Eigen::VectorXd pathGradientAt(const DeformationEnergy& energy, const Eigen::VectorXd& x, const Eigen::VectorXd* prev,
                               const Eigen::VectorXd* next);

}  // namespace deformation_enrichment::shape_space
