#pragma once
// Example acquisition of [Seiler14 §3] on any scene file (docs/design.md §1, §6): for one tool interaction
// run the COARSE and the FINE quasi-static simulation with the same tool motion, interpolate the coarse
// solution onto the display surface through the barycentric embedding, take d = fine - coarse there,
// describe the contact (p, B, R, rho, mu) from the coarse state with the ContactEnricher (the very code the
// run time uses) and store Psi = B^T R^T d in the example frame: d of the volume around the contact on a
// volume stamp's nodes, or d of the display surface rasterised on a surface stamp (enrichment/stamp.hpp). The enricher works on the display
// surface; its "current" state is the coarse solution carried onto that surface, here and at run time.
#include <Eigen/Core>
#include <iosfwd>
#include <memory>
#include <string>
#include <vector>

#include "deformation_enrichment/acquisition/plan_io.hpp"
#include "deformation_enrichment/acquisition/recorded_coarse.hpp"
#include "deformation_enrichment/enrichment/contact_enricher.hpp"
#include "deformation_enrichment/examples/example.hpp"
#include "deformation_enrichment/mesh/triangle_mesh.hpp"
#include "deformation_enrichment/scene_file/scene_description.hpp"
#include "deformation_enrichment/scenes/scene_models.hpp"

namespace deformation_enrichment::acquisition {

/// A plan entry as the tool meets the display surface: the point projected onto it, the inward normal there
/// (the indentation direction) and the tangential part of the drag.
struct ToolPath {
  Eigen::Vector3d contact = Eigen::Vector3d::Zero();
  Eigen::Vector3d inward = -Eigen::Vector3d::UnitZ();
  double depth = 0.0;
  Eigen::Vector3d drag = Eigen::Vector3d::Zero();
};

/// Surface states of one interaction on the display surface's vertices.
struct InteractionResult {
  Eigen::Matrix3Xd coarseOnFine;  ///< coarse solution interpolated through the embedding
  Eigen::Matrix3Xd fine;          ///< fine solution
  Eigen::Matrix3Xd coarseNodes;   ///< coarse solution at the coarse volume's nodes
  Eigen::Matrix3Xd fineNodes;     ///< fine solution at the fine volume's nodes
  double coarseSeconds = 0.0, fineSeconds = 0.0;
  bool converged = true;
  std::string message;            ///< solver messages when not converged
};

/// Every `count`-th plan line starting at line `index` (1-based), for acquisition in parallel jobs.
struct Shard {
  int index = 1, count = 1;
  bool holds(std::size_t planLine) const { return static_cast<int>(planLine % static_cast<std::size_t>(count)) == index - 1; }
};

/// The enricher options a scene's examples are described with (window, cut-off, quadrature, sampling,
/// stamp radius from the scene file; orders rho 0..3, mu 1..2 [Seiler14 Table 1]).
enrichment::ContactEnricherOptions enricherOptions(const scene_file::SceneDescription& scene);

/// The provenance a set acquired on `scene` records (the scene with its files reduced to names and hashes;
/// with `coarse`, also its recording's hash and simulator).
examples::Provenance provenanceOf(const scene_file::SceneDescription& scene, const RecordedCoarse* coarse = nullptr);

/// Where the default example set of a scene is cached: $DE_EXAMPLE_CACHE/<scene> when that variable is set,
/// else $XDG_CACHE_HOME (or ~/.cache)/deformation_enrichment/example_sets/<scene>.
std::string defaultExampleSetDirectory(const std::string& scene);

class SceneAcquisition {
public:
  /// Builds both models, the display surface, the embedding (refusing display vertices farther than the
  /// scene's max_outside from the coarse volume) and the ContactEnricher. Throws InvalidInputError / IoError
  /// naming the file or key for an unusable scene.
  explicit SceneAcquisition(scene_file::SceneDescription scene);
  ~SceneAcquisition();

  const scene_file::SceneDescription& scene() const { return scene_; }
  const scenes::SceneModels& models() const;
  const mesh::TriangleMesh& fineSurface() const;
  enrichment::ContactEnricher& enricher();
  /// Display vertices outside the coarse volume (count, largest distance in m): the embedding extrapolates.
  std::pair<long, double> outsideVertices() const;

  /// The entry's tool path. Throws InvalidInputError when its point is farther than the stamp radius from
  /// the display surface, or lands on the fixed region.
  ToolPath toolPath(const PlanEntry& entry) const;

  /// Where the tool sphere's centre is at each step of the entry's path (step 0: touching the rest surface at
  /// the contact, one tool radius outside it; then every indentation and drag step): the commands of the
  /// coarse-simulator contract (docs/coarse_simulator.md).
  std::vector<Eigen::Vector3d> toolCentres(const PlanEntry& entry) const;

  /// Coarse and fine solves of one interaction.
  InteractionResult simulate(const PlanEntry& entry) const;
  /// The fine solve of one interaction whose coarse half comes from another simulator: `coarseOnSurface`, the
  /// display-surface state it settled in (docs/coarse_simulator.md). The coarse volume nodes (for volume
  /// stamps) are fitted to it through the embedding (mesh/embedded_state_fit.hpp). Throws InvalidInputError
  /// for a state of another size than the display surface or a non-finite one.
  InteractionResult simulate(const PlanEntry& entry, const Eigen::Matrix3Xd& coarseOnSurface) const;

  /// Which of the scene's two simulations: the coarse one (what runs live) or the fine one (the truth).
  enum class Resolution { Coarse, Fine };
  /// The quasi-static path of an interaction in one simulation, on the display surface: the rest state, then
  /// the state after each of `indentSteps` indentation and `dragSteps` drag steps (none without a drag).
  /// Solver messages of unconverged steps go to `message`. For playing a simulation (the demo: the coarse
  /// one enriched, the fine one as the truth beside it).
  std::vector<Eigen::Matrix3Xd> surfacePath(Resolution model, const PlanEntry& entry, int indentSteps, int dragSteps,
                                            std::string* message = nullptr) const;

  /// The example of an interaction (descriptors from the coarse state, stamp from d = fine - coarse).
  examples::Example makeExample(const PlanEntry& entry, const InteractionResult& result);

  /// The enricher's contact for a plan entry (the tool path's contact, in the rest state, tool 0).
  enrichment::Contact contactOf(const PlanEntry& entry) const;

  /// Acquires the plan lines of `shard` into the set at `directory`, rewriting it after each example so that
  /// an interrupted run resumes: examples already there with the same plan line, contact, pattern and
  /// provenance are kept, not recomputed. Progress lines (seconds, peak memory) go to `log` when given.
  /// With `coarse`, the plan is the recording's and each line's coarse half is its settled state; lines
  /// the recording has no state of (skipped by the driver) are left out and named in the log.
  examples::ExampleSet acquireSet(const std::vector<PlanEntry>& plan, const std::string& directory,
                                  std::ostream* log = nullptr, const Shard& shard = {},
                                  const RecordedCoarse* coarse = nullptr);

private:
  /// The fine half of `r`: fine, fineNodes, fineSeconds (and converged, message when it is not).
  void solveFine(const ToolPath& path, InteractionResult& r) const;
  Eigen::Matrix3Xd coarseOnFineSurface(const Eigen::Matrix3Xd& coarse) const;
  Eigen::Matrix3Xd fineOnSurface(const Eigen::Matrix3Xd& fine) const;
  /// The volume stamp of an interaction: B^T R^T (fine - coarse) at the stamp's nodes (`toFrame` = B^T R^T).
  cv::Mat volumeStamp(const InteractionResult& result, const Eigen::Vector3d& p, const Eigen::Matrix3d& B,
                      const Eigen::Matrix3d& toFrame) const;
  struct Impl;
  scene_file::SceneDescription scene_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace deformation_enrichment::acquisition
