#pragma once
// One object's run-time enrichment without ROS (docs/design.md §6): the rest surface and the volume around
// it, the example set, the run-time knobs, the ContactEnricher built from them, a stream's continuity and
// temporal filter, and the unchanged-input memo. The ROS node converts messages, fills the options from
// parameters and publishes; everything between a mesh state and its enriched positions happens here.
//
// Threads: enrich() runs on the frame thread. A new rest surface (a cut) is built on the session's own worker
// thread; meanwhile states of the old size are enriched with the old enricher and states of the new size pass
// through, and the new enricher takes over at the start of a state. A new example set or Hermite order is
// built on the caller's thread (a service), outside the frame lock, then swapped in. All methods may be
// called from any thread.
#include <Eigen/Core>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "deformation_enrichment/descriptors/site_density.hpp"
#include "deformation_enrichment/enrichment/contact_continuity.hpp"
#include "deformation_enrichment/enrichment/contact_enricher.hpp"
#include "deformation_enrichment/enrichment/input_memo.hpp"
#include "deformation_enrichment/enrichment/temporal_filter.hpp"
#include "deformation_enrichment/examples/example.hpp"
#include "deformation_enrichment/mesh/tet_mesh.hpp"
#include "deformation_enrichment/mesh/triangle_mesh.hpp"
#include "deformation_enrichment/scene_file/scene_description.hpp"

namespace deformation_enrichment::enrichment {

/// The run-time knobs (the node's dynamic_reconfigure parameters).
struct KnobOptions {
  BlendMethod blend = BlendMethod::Regression;  ///< how examples are blended (example_blender.hpp)
  DetailGain gain;
  double sigmaRho = 0.0, sigmaU = 0.0;  ///< <= 0: the set's leave-one-out fitted width
  int hermiteOrder = 0;                 ///< 0: the order the set was built with
  double temporalSmoothing = 0.0;       ///< TemporalFilter time constant [s] (0 = off)
};

enum class SessionLogLevel { Info, Warning, Error };

struct SessionOptions {
  /// Descriptor options a set does not record (window scale, sample spacing) and the run-time-only ones
  /// (rim band, bounds); everything a set records comes from the set (optionsFor).
  ContactEnricherOptions defaults;
  /// Where rho's density comes from. `spacing` is ignored (the set's sample spacing is used, as in
  /// acquisition); a shellThickness <= 0 means three window scales of the set.
  descriptors::SiteDensityOptions density{descriptors::SiteDensitySource::Auto, 0.0015, 0.0, 0.002};
  ContactContinuityOptions continuity;
  /// How a loaded set is blended: the RBF's lambda and the cross-validated gain (the method comes from the
  /// knobs, the rest as ExampleBlenderOptions' defaults).
  ExampleBlenderOptions blending;
  /// The tissue being enriched, when known: a set acquired on another material has its stamps scaled by
  /// materialSimilarity(set's scene, this scene) (material_similarity.hpp); none, or a set without
  /// provenance: 1.
  std::optional<scene_file::SceneDescription> scene;
  /// A set acquired on another scene than `scene` has its stamps scaled by this instead of the material
  /// similarity when > 0: a transfer gain calibrated on fine solves of this scene (de_evaluate --calibrate,
  /// transfer_calibration.hpp). It belongs to one set on one scene.
  double transferGain = 0.0;
  /// Receives what the worker did (a rest surface built or refused); called from the worker thread.
  std::function<void(SessionLogLevel, const std::string&)> log;
};

/// A rest surface and, optionally, the volume it is embedded in (metres, the mesh state's frame).
struct RestGeometry {
  mesh::TriangleMesh surface;
  std::optional<mesh::TetMesh> volume;
  std::string source;  ///< where it came from, for logs
};

/// A rest geometry the session accepted.
struct RestSurface {
  RestGeometry geometry;
  Eigen::Matrix3Xd normals;  ///< area-weighted vertex normals of the surface
  std::uint64_t version = 0; ///< increases with every accepted rest geometry
};

/// One tool touching the current state: where (a current-state point), and which tool.
struct ToolContact {
  std::string toolId;
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
};

/// What enrich() made of one state.
struct FrameResult {
  enum class Kind { PassedThrough, Enriched, Reused };
  Kind kind = Kind::PassedThrough;
  bool changed = false;  ///< some vertex was displaced (else the enriched state equals the input)
  bool restPending = false;  ///< the state belongs to a rest surface still being built (it passes through)
  std::uint32_t verticesTouched = 0;
  std::uint32_t releasedSites = 0;
  float confidence = 0.0f;                 ///< largest eq. (15) weight over the contacts
  std::vector<std::uint32_t> exampleIds;   ///< examples with |w~| >= 1e-3, parallel to weights
  std::vector<float> weights;
  std::string note;   ///< why a state was passed through although tools touch it (e.g. a rebuild)
  std::string error;  ///< the enrichment failed for this state (it passes through; the stream's memory stays)
};

struct SessionDiagnostics {
  Eigen::Index restVertices = 0;      ///< of the active rest surface (0: none)
  std::string siteDensity;            ///< how the active enricher's rho density was made
  bool rebuilding = false;            ///< a rest surface is being built
  std::uint64_t rebuilds = 0, supersededRebuilds = 0;
  double lastRebuildSeconds = 0.0;
  std::string lastRestError;
  bool hasExamples = false;
  int hermiteOrder = 0;               ///< in use (0: no enricher)
  KernelWidths widths, fittedWidths;
  std::string blend;                  ///< the active blend ("paper", "regression"; empty: no enricher)
  double materialSimilarity = 1.0;    ///< of the active set's scene and this scene's material
  double stampScale = 1.0;            ///< on the active set's stamps: the similarity or the transfer gain
  std::uint64_t statesReused = 0;
};

class EnrichmentSession {
public:
  /// Throws InvalidInputError for bad continuity or density options.
  explicit EnrichmentSession(SessionOptions options);
  ~EnrichmentSession();
  EnrichmentSession(const EnrichmentSession&) = delete;
  EnrichmentSession& operator=(const EnrichmentSession&) = delete;

  /// Checks `rest` (a surface with vertices and triangles, indices in range, finite; a valid volume) and
  /// hands it to the worker, which builds its enricher; returns at once. The same surface and volume as the
  /// newest accepted one is ignored (a latched topic sends it to every new connection). A newer rest
  /// supersedes one still being built. Throws InvalidInputError naming the problem; nothing changes then.
  void setRestGeometry(RestGeometry rest);

  /// Builds the enricher for `set` with the current knobs on the calling thread, then installs both. A
  /// Hermite order above the set's runs at the set's (warned through the log). Throws InvalidInputError
  /// (empty set, layouts or radii that differ from the options) leaving the previous set active.
  void setExampleSet(examples::ExampleSet set);

  /// Applies the knobs from the next state on; a new Hermite order rebuilds the enricher on the calling
  /// thread. Throws InvalidInputError (an order above the active set's, a non-finite width or gain, a
  /// confidence outside [0, 1], a negative time constant) leaving every knob as it was.
  void setKnobs(const KnobOptions& knobs);
  KnobOptions knobs() const;

  /// Enriches the state `positions` (3 x vertices of the active or the pending rest surface) for the tools
  /// touching it; `stampSeconds` is the state's time (the temporal filter's dt). Throws InvalidInputError
  /// for a state that fits no rest surface or is not finite, and NumericalError for a non-finite result;
  /// the last good state and the stream's memory are kept then. When the result says `changed`, the
  /// enriched positions are enrichedPositions() until the next call; otherwise they are the input.
  const FrameResult& enrich(const Eigen::Matrix3Xf& positions, const std::vector<ToolContact>& touching, double stampSeconds);
  const Eigen::Matrix3Xf& enrichedPositions() const { return enriched_; }

  /// The rest surface states of `vertices` points belong to (the active one, else the one being built),
  /// or null.
  std::shared_ptr<const RestSurface> restFor(Eigen::Index vertices) const;
  /// The newest accepted rest surface (being built or active), or null.
  std::shared_ptr<const RestSurface> newestRest() const;
  bool hasExampleSet() const;
  std::size_t exampleCount() const;
  SessionDiagnostics diagnostics() const;

  /// Blocks until no rest surface is being built (tests, tools).
  void waitForRebuild() const;

private:
  struct Built;
  /// The enricher for `rest`, `set` and `knobs` (density, descriptor options from the set, kernel widths);
  /// throws InvalidInputError.
  std::unique_ptr<Built> build(const RestSurface& rest, const examples::ExampleSet& set, const KnobOptions& knobs) const;
  /// The worker: builds the newest pending rest surface and installs it between two states.
  void rebuildLoop();
  /// Builds the enricher for `set` and `knobs` on the active rest surface (outside the lock) and installs
  /// all three; throws InvalidInputError, leaving everything as it was.
  void installConfiguration(std::shared_ptr<const examples::ExampleSet> set, const KnobOptions& knobs);
  void resetStream();
  void enrichContacts(const Eigen::Matrix3Xf& positions, const std::vector<Contact>& contacts, double dt);
  void log(SessionLogLevel level, const std::string& text) const;

  const SessionOptions options_;
  mutable std::mutex mutex_;
  mutable std::condition_variable changed_;
  // Guarded by mutex_.
  std::shared_ptr<const RestSurface> active_;    // what states are enriched on
  std::shared_ptr<const RestSurface> pending_;   // accepted, being built (null: none)
  std::unique_ptr<Built> enricher_;              // for active_ (null: no rest; its enricher null: no set)
  std::shared_ptr<const examples::ExampleSet> set_;
  KnobOptions knobs_;
  std::uint64_t configVersion_ = 0;              // bumped by every new set, enricher or knob value
  std::uint64_t nextRestVersion_ = 1;
  bool building_ = false, stopping_ = false;
  SessionDiagnostics stats_;
  // Frame state (guarded by mutex_).
  ContactContinuity continuity_;
  TemporalFilter temporalFilter_;
  std::map<std::string, int> toolNumbers_;
  EnrichmentResult scratch_;
  FrameResult result_;
  Eigen::Matrix3Xf enriched_;
  std::optional<double> lastStamp_;
  InputMemo memo_;  // valid only while its state was the last enriched (result_ and enriched_ hold its outcome)

  std::thread worker_;  // last: starts after every member above exists
};

}  // namespace deformation_enrichment::enrichment
