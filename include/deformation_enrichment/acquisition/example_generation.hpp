#pragma once
// Example acquisition of [Seiler14 §3] on the slab scene (docs/design.md §1, §4): for one tool interaction run
// the COARSE and the FINE quasi-static simulation with the same tool motion, interpolate the coarse
// solution onto the fine surface through the barycentric embedding, take d = fine - coarse on the fine
// surface vertices, describe the contact (p, B, R, rho, mu) from the coarse state with the ContactEnricher
// (the very code the run time uses) and rasterise Psi = B^T R^T d in the example frame.
// The enricher works on the fine (display) surface; its "current" state is the coarse solution carried
// onto that surface by the embedding, both here and at run time.
#include <Eigen/Core>
#include <iosfwd>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "deformation_enrichment/acquisition/plan_io.hpp"
#include "deformation_enrichment/enrichment/contact_enricher.hpp"
#include "deformation_enrichment/examples/example.hpp"
#include "deformation_enrichment/mesh/triangle_mesh.hpp"
#include "deformation_enrichment/scenes/procedural_scene.hpp"

namespace deformation_enrichment::acquisition {

/// Ten indent / drag interactions on the slab top (|x|, |y| <= 0.02 m, depths 2-4 mm, drags 0-6 mm).
std::vector<PlanEntry> defaultSlabPlan();
/// Held-out interactions between those of the default plan (for de_evaluate).
std::vector<PlanEntry> heldOutSlabContacts();

/// How the tool loads the tissue (scenes/tool_loading.hpp). Penalty is smooth in the tool position, so the
/// fine-minus-coarse difference varies smoothly between acquisition contacts; Dirichlet grabs whole
/// vertices and makes it jump with the mesh.
enum class ToolModel { Dirichlet, Penalty };

struct SlabAcquisitionOptions {
  /// Coarse: 10 x 10 cells, 2 bulk layers + 1 skin layer (1 cm cells). Fine: 24 x 24 cells, 4 bulk layers
  /// + 2 skin layers (4.2 mm cells). Both carry the same 1 mm skin so their rest surfaces coincide.
  /// Measured (Release, shared 2 cores): the default 10-line plan takes ~70 s (fine solve 3.5-10 s per
  /// interaction, coarse ~0.2 s); the fine surface has 1730 vertices.
  scenes::Layering coarse{Eigen::Vector3i(10, 10, 2), 0.001, 1};
  scenes::Layering fine{Eigen::Vector3i(24, 24, 4), 0.001, 2};
  double bulkYoung = 1e4, bulkPoisson = 0.45;  ///< Pa; soft tissue
  double skinYoung = 1e6, skinPoisson = 0.3;   ///< Pa; stiff skin
  /// Skin Young's modulus of the coarse model (Pa); 0 = skinYoung.
  double coarseSkinYoung = 0.0;
  double toolRadius = 0.005;   ///< footprint radius (m); a Dirichlet coarse footprint is widened to reach a vertex
  ToolModel toolModel = ToolModel::Penalty;
  /// Penalty stiffness per area (Pa/m): total tool stiffness 1e9 * pi (5 mm)^2 / 3 = 2.6e4 N/m, so the
  /// skin slips ~0.04 mm under a 1 N tool force.
  double toolStiffness = 1e9;
  int indentSteps = 2, dragSteps = 2;
  double relativeTolerance = 1e-7;
  /// Held-out enriched / coarse RMS is 0.424, 0.419, 0.420, 0.421 at 8, 16, 32, 64 nodes (fine surface
  /// cells are 4.2 mm, nodes 0.9-8.6 mm apart): 32 keeps nodes under half a fine cell at 12 KB a stamp.
  int stampResolution = 32;
  enrichment::ContactEnricherOptions enricher = defaultEnricherOptions();

  static enrichment::ContactEnricherOptions defaultEnricherOptions();
};

/// Surface states of one interaction on the fine surface's vertices.
struct InteractionResult {
  Eigen::Matrix3Xd coarseOnFine;  ///< coarse solution interpolated through the embedding
  Eigen::Matrix3Xd fine;          ///< fine solution
  double coarseSeconds = 0.0, fineSeconds = 0.0;
  bool converged = true;
  std::string message;            ///< solver messages when not converged
};

/// Where the default example set of a scene is cached: $DE_EXAMPLE_CACHE/<scene> when that variable is set,
/// else $XDG_CACHE_HOME (or ~/.cache)/deformation_enrichment/example_sets/<scene>.
std::string defaultExampleSetDirectory(const std::string& scene);

/// Restores the resolutions and tool model a set was acquired with (materialMetadata keys) and its descriptor
/// options (enrichment::optionsFor), so that evaluation rebuilds the same coarse / fine slabs and descriptors.
void applyResolutionMetadata(const examples::ExampleSet& set, SlabAcquisitionOptions& options);

class SlabAcquisition {
public:
  /// Builds both scenes, their FEM models, the fine surface, the embedding and the ContactEnricher.
  /// Throws InvalidInputError for invalid options (resolutions, materials, a negative or non-finite
  /// coarseSkinYoung, descriptor options).
  explicit SlabAcquisition(const SlabAcquisitionOptions& options = SlabAcquisitionOptions());
  ~SlabAcquisition();

  const SlabAcquisitionOptions& options() const { return options_; }
  const mesh::TriangleMesh& fineSurface() const;
  enrichment::ContactEnricher& enricher();
  std::map<std::string, double> materialMetadata() const;

  /// Coarse and fine solves of one interaction (throws InvalidInputError if the tool misses the top).
  InteractionResult simulate(const PlanEntry& entry) const;

  /// The coarse quasi-static path of an interaction on the fine surface: the rest state, then the state
  /// after each of `indentSteps` indentation and `dragSteps` drag steps (no drag steps without a drag).
  /// Solver messages of unconverged steps go to `message`. For playing a coarse simulation (the demo).
  std::vector<Eigen::Matrix3Xd> coarsePath(const PlanEntry& entry, int indentSteps, int dragSteps,
                                           std::string* message = nullptr) const;

  /// The example of an interaction (descriptors from the coarse state, stamp from d = fine - coarse).
  examples::Example makeExample(const PlanEntry& entry, const InteractionResult& result);

  /// The enricher's contact for a plan entry (rest-state point, tool 0).
  static enrichment::Contact contactOf(const PlanEntry& entry);

  /// Acquires every plan entry into the set at `directory`, rewriting it after each example so that an
  /// interrupted run resumes: examples already there with the same contact, pattern, stamp resolution
  /// and material metadata are kept, not recomputed. Progress lines go to `log` when given.
  examples::ExampleSet acquireSet(const std::vector<PlanEntry>& plan, const std::string& directory, std::ostream* log = nullptr);

private:
  Eigen::Matrix3Xd coarseOnFineSurface(const Eigen::Matrix3Xd& coarse) const;
  struct Impl;
  SlabAcquisitionOptions options_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace deformation_enrichment::acquisition
