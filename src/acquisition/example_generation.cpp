#include "deformation_enrichment/acquisition/example_generation.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <ostream>

#include "deformation_enrichment/elasticity/quasi_static_solver.hpp"
#include "deformation_enrichment/elasticity/tet_fem.hpp"
#include "deformation_enrichment/enrichment/example_set_options.hpp"
#include "deformation_enrichment/enrichment/stamp.hpp"
#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/examples/example_set_io.hpp"
#include "deformation_enrichment/mesh/barycentric_embedding.hpp"
#include "deformation_enrichment/mesh/tet_surface.hpp"
#include "deformation_enrichment/scenes/tool_loading.hpp"

namespace deformation_enrichment::acquisition {
namespace {

using Clock = std::chrono::steady_clock;

PlanEntry entry(double x, double y, double depth, double dx, double dy) {
  PlanEntry e;
  e.point = Eigen::Vector3d(x, y, 0.02);
  e.depth = depth;
  e.drag = Eigen::Vector3d(dx, dy, 0.0);
  return e;
}

// One body (coarse or fine) with its solver.
struct Body {
  scenes::Scene scene;
  std::unique_ptr<elasticity::TetFem> fem;
  double cellSize = 0.0;  // largest lateral cell size (m)
};

Body makeBody(const scenes::Layering& layering, double skinYoung, const SlabAcquisitionOptions& o) {
  Body body;
  scenes::SlabOptions slab;
  slab.layering = layering;
  body.scene = scenes::makeSlab(slab);
  const auto bulk = elasticity::lameFromYoungPoisson(o.bulkYoung, o.bulkPoisson);
  const auto skin = elasticity::lameFromYoungPoisson(skinYoung, o.skinPoisson);
  body.fem = std::make_unique<elasticity::TetFem>(
      body.scene.mesh,
      std::vector<elasticity::StableNeoHookean>{elasticity::StableNeoHookean(bulk.mu, bulk.lambda),
                                                elasticity::StableNeoHookean(skin.mu, skin.lambda)},
      body.scene.materialId);
  const Eigen::Vector3d extent = slab.hi - slab.lo;
  body.cellSize = std::max(extent.x() / layering.cells.x(), extent.y() / layering.cells.y());
  return body;
}

// Quasi-static path: indent along -z (the slab top's inward normal) in `indentSteps`, then drag in
// `dragSteps`; `onStep` (optional) sees the positions after every step. Returns seconds.
double solvePath(const Body& body, const PlanEntry& e, const SlabAcquisitionOptions& o, int indentSteps, int dragSteps,
                 Eigen::Matrix3Xd& positions, bool& converged, std::string& message,
                 const std::function<void(const Eigen::Matrix3Xd&)>& onStep = {}) {
  const auto start = Clock::now();
  // Dirichlet: a coarse grid may have no vertex within the tool radius, so the footprint widens to reach
  // one (~0.71 cell). Penalty: the footprint integral loads whichever vertices' hat functions it covers.
  std::vector<int> tool;
  elasticity::AnchorSprings springs;
  Eigen::Matrix3Xd springRest;
  if (o.toolModel == ToolModel::Dirichlet) {
    tool = scenes::toolFootprint(body.scene, e.point.head<2>(), std::max(o.toolRadius, 0.75 * body.cellSize));
  } else {
    springs = scenes::toolSprings(body.scene, e.point, o.toolRadius, o.toolStiffness);
    springRest = springs.targets;
  }
  const double dragDistance = e.drag.norm();
  if (dragDistance == 0.0) dragSteps = 0;
  const Eigen::Vector3d dragDirection = dragDistance > 0.0 ? Eigen::Vector3d(e.drag / dragDistance) : Eigen::Vector3d::UnitX();
  elasticity::SolverSettings settings;
  settings.relativeForceTolerance = o.relativeTolerance;
  elasticity::QuasiStaticSolver solver(*body.fem, settings);
  positions = body.scene.mesh.vertices;
  for (int step = 1; step <= indentSteps + dragSteps; ++step) {
    const Eigen::Vector3d u = scenes::toolDisplacement(step, indentSteps, dragSteps, -Eigen::Vector3d::UnitZ(), e.depth,
                                                       dragDirection, dragDistance);
    elasticity::SolveResult r;
    if (o.toolModel == ToolModel::Dirichlet) {
      r = solver.solve(positions, scenes::toolConstraints(body.scene, tool, u));
    } else {
      springs.targets = springRest.colwise() + u;
      r = solver.solve(positions, scenes::supportConstraints(body.scene), springs);
    }
    if (!r.converged()) {
      converged = false;
      message += "step " + std::to_string(step) + ": " + r.message + "; ";
    }
    if (onStep) onStep(positions);
  }
  return std::chrono::duration<double>(Clock::now() - start).count();
}

}  // namespace

void applyResolutionMetadata(const examples::ExampleSet& set, SlabAcquisitionOptions& options) {
  const std::map<std::string, double>& material = set.metadata.material;
  const auto get = [&](const char* key, int& value) {
    const auto it = material.find(key);
    if (it != material.end()) value = static_cast<int>(std::lround(it->second));
  };
  get("coarse_cells_x", options.coarse.cells.x());
  get("coarse_cells_y", options.coarse.cells.y());
  get("coarse_cells_z", options.coarse.cells.z());
  get("fine_cells_x", options.fine.cells.x());
  get("fine_cells_y", options.fine.cells.y());
  get("fine_cells_z", options.fine.cells.z());
  get("fine_skin_layers", options.fine.skinLayers);
  const auto tool = material.find("tool_radius_m");
  if (tool != material.end()) options.toolRadius = tool->second;
  // Sets written before the penalty tool existed carry no tool model: they used the Dirichlet tool.
  const auto model = material.find("tool_model");
  options.toolModel = model != material.end() && model->second == 1.0 ? ToolModel::Penalty : ToolModel::Dirichlet;
  const auto stiffness = material.find("tool_stiffness_pa_per_m");
  if (stiffness != material.end()) options.toolStiffness = stiffness->second;
  const auto coarseSkin = material.find("coarse_skin_young_pa");
  if (coarseSkin != material.end()) options.coarseSkinYoung = coarseSkin->second;
  options.enricher = enrichment::optionsFor(set, options.enricher);
}

std::vector<PlanEntry> defaultSlabPlan() {
  return {entry(0.0, 0.0, 0.003, 0.0, 0.0),        entry(0.015, 0.0, 0.003, 0.005, 0.0),
          entry(-0.015, 0.01, 0.004, 0.0, 0.005),   entry(0.01, -0.015, 0.002, -0.004, 0.0),
          entry(-0.01, -0.01, 0.003, 0.004, 0.004), entry(0.02, 0.02, 0.004, 0.0, 0.0),
          entry(0.0, 0.02, 0.003, 0.006, 0.0),      entry(-0.02, 0.0, 0.002, 0.0, -0.005),
          entry(0.005, 0.015, 0.004, -0.003, 0.003), entry(-0.005, -0.02, 0.003, 0.0, 0.0)};
}

std::vector<PlanEntry> heldOutSlabContacts() {
  return {entry(0.007, 0.004, 0.003, 0.003, 0.0), entry(-0.012, -0.004, 0.0035, 0.0, 0.0),
          entry(0.012, -0.008, 0.0025, 0.0, 0.004), entry(-0.006, 0.012, 0.003, 0.004, 0.002)};
}

enrichment::ContactEnricherOptions SlabAcquisitionOptions::defaultEnricherOptions() {
  enrichment::ContactEnricherOptions o;
  o.descriptors.window.scale = 0.006;  // h: a tool-sized window
  // The coarse (1 cm cells) dent is wider than the fine one: fine - coarse is still ~1/3 of its peak at
  // 2 cm. Held-out enriched / coarse RMS with rim band 0.2: 0.49 at R = 2 cm, 0.45 at 2.5 cm, 0.42 at 3 cm.
  o.stampRadius = 0.03;
  o.sampleSpacing = 0.002;
  return o;
}

struct SlabAcquisition::Impl {
  Body coarse, fine;
  mesh::TetSurface fineSurface;
  Eigen::Matrix3Xd fineSurfaceRest;
  mesh::BarycentricEmbedding embedding;
  std::unique_ptr<enrichment::ContactEnricher> enricher;
};

SlabAcquisition::SlabAcquisition(const SlabAcquisitionOptions& options) : options_(options), impl_(std::make_unique<Impl>()) {
  if (!(options.coarseSkinYoung >= 0.0) || !std::isfinite(options.coarseSkinYoung))
    throw InvalidInputError("acquisition: the coarse skin's Young's modulus must be finite and >= 0 (0: the fine one's)");
  impl_->coarse = makeBody(options.coarse, options.coarseSkinYoung > 0.0 ? options.coarseSkinYoung : options.skinYoung, options);
  impl_->fine = makeBody(options.fine, options.skinYoung, options);
  impl_->fineSurface = mesh::extractSurface(impl_->fine.scene.mesh);
  impl_->fineSurfaceRest = impl_->fineSurface.surface.vertices;
  // Both slabs fill the same box, so every fine surface vertex lies in (or on) the coarse mesh.
  impl_->embedding = mesh::embedPoints(impl_->coarse.scene.mesh, impl_->fineSurfaceRest, 1e-9);
  impl_->enricher = std::make_unique<enrichment::ContactEnricher>(impl_->fineSurface.surface, options.enricher);
}

SlabAcquisition::~SlabAcquisition() = default;

const mesh::TriangleMesh& SlabAcquisition::fineSurface() const { return impl_->fineSurface.surface; }
enrichment::ContactEnricher& SlabAcquisition::enricher() { return *impl_->enricher; }

std::map<std::string, double> SlabAcquisition::materialMetadata() const {
  std::map<std::string, double> metadata = enrichment::descriptorMetadata(options_.enricher);
  metadata.insert({{"bulk_young_pa", options_.bulkYoung}, {"bulk_poisson", options_.bulkPoisson},
          {"skin_young_pa", options_.skinYoung}, {"skin_poisson", options_.skinPoisson},
          {"coarse_skin_young_pa", options_.coarseSkinYoung > 0.0 ? options_.coarseSkinYoung : options_.skinYoung},
          {"skin_thickness_m", options_.fine.skinThickness}, {"tool_radius_m", options_.toolRadius},
          {"tool_model", options_.toolModel == ToolModel::Penalty ? 1.0 : 0.0},
          {"tool_stiffness_pa_per_m", options_.toolStiffness},
          {"coarse_cells_x", options_.coarse.cells.x()}, {"coarse_cells_y", options_.coarse.cells.y()},
          {"coarse_cells_z", options_.coarse.cells.z()}, {"fine_cells_x", options_.fine.cells.x()},
          {"fine_cells_y", options_.fine.cells.y()}, {"fine_cells_z", options_.fine.cells.z()},
          {"fine_skin_layers", options_.fine.skinLayers}});
  return metadata;
}

enrichment::Contact SlabAcquisition::contactOf(const PlanEntry& entry) {
  enrichment::Contact c;
  c.point = entry.point;
  return c;
}

InteractionResult SlabAcquisition::simulate(const PlanEntry& entry) const {
  if (!entry.point.allFinite() || !entry.drag.allFinite() || !std::isfinite(entry.depth) || entry.depth < 0.0)
    throw InvalidInputError("acquisition: non-finite interaction or negative depth");
  InteractionResult r;
  Eigen::Matrix3Xd coarse, fine;
  r.coarseSeconds = solvePath(impl_->coarse, entry, options_, options_.indentSteps, options_.dragSteps, coarse, r.converged, r.message);
  r.fineSeconds = solvePath(impl_->fine, entry, options_, options_.indentSteps, options_.dragSteps, fine, r.converged, r.message);
  r.coarseOnFine = coarseOnFineSurface(coarse);
  r.fine.resize(3, impl_->fineSurfaceRest.cols());
  for (Eigen::Index v = 0; v < r.fine.cols(); ++v) r.fine.col(v) = fine.col(impl_->fineSurface.surfaceToVolume[static_cast<std::size_t>(v)]);
  return r;
}

Eigen::Matrix3Xd SlabAcquisition::coarseOnFineSurface(const Eigen::Matrix3Xd& coarse) const {
  // The coarse displacement carried onto the fine surface (exact for the coarse tets' affine fields).
  return impl_->fineSurfaceRest +
         mesh::interpolate(impl_->embedding, impl_->coarse.scene.mesh, coarse - impl_->coarse.scene.mesh.vertices);
}

std::vector<Eigen::Matrix3Xd> SlabAcquisition::coarsePath(const PlanEntry& entry, int indentSteps, int dragSteps,
                                                          std::string* message) const {
  if (!entry.point.allFinite() || !entry.drag.allFinite() || !std::isfinite(entry.depth) || entry.depth < 0.0)
    throw InvalidInputError("acquisition: non-finite interaction or negative depth");
  if (indentSteps < 1 || dragSteps < 0) throw InvalidInputError("coarsePath: needs indentSteps >= 1 and dragSteps >= 0");
  std::vector<Eigen::Matrix3Xd> path{impl_->fineSurfaceRest};
  Eigen::Matrix3Xd coarse;
  bool converged = true;
  std::string log;
  solvePath(impl_->coarse, entry, options_, indentSteps, dragSteps, coarse, converged, log,
            [&](const Eigen::Matrix3Xd& positions) { path.push_back(coarseOnFineSurface(positions)); });
  if (message) *message = log;
  return path;
}

examples::Example SlabAcquisition::makeExample(const PlanEntry& entry, const InteractionResult& result) {
  const enrichment::ContactDescription d = impl_->enricher->describe(result.coarseOnFine, contactOf(entry));
  const double R = options_.enricher.stampRadius;
  const mesh::TriangleMesh& surface = impl_->fineSurface.surface;
  // The patch seen from outside along b_z within the stamp square: rasterisation needs only these.
  std::vector<int> toPatch(static_cast<std::size_t>(surface.vertices.cols()), -1);
  std::vector<int> patchVertices;
  std::vector<Eigen::Vector3i> patchTriangles;
  const double reach = std::sqrt(2.0) * R + 2.0 * impl_->fine.cellSize;
  for (Eigen::Index f = 0; f < surface.triangles.cols(); ++f) {
    const Eigen::Vector3i t = surface.triangles.col(f);
    const Eigen::Vector3d a = surface.vertices.col(t(0)), b = surface.vertices.col(t(1)), c = surface.vertices.col(t(2));
    if ((b - a).cross(c - a).dot(d.B.col(2)) <= 0.0) continue;
    if ((a - d.p).norm() > reach || (b - d.p).norm() > reach || (c - d.p).norm() > reach) continue;
    Eigen::Vector3i local;
    for (int k = 0; k < 3; ++k) {
      int& id = toPatch[static_cast<std::size_t>(t(k))];
      if (id < 0) {
        id = static_cast<int>(patchVertices.size());
        patchVertices.push_back(t(k));
      }
      local(k) = id;
    }
    patchTriangles.push_back(local);
  }
  if (patchTriangles.empty()) throw InvalidInputError("acquisition: no surface facing the contact's normal near it");
  mesh::TriangleMesh patch;
  patch.vertices.resize(3, static_cast<Eigen::Index>(patchVertices.size()));
  patch.triangles.resize(3, static_cast<Eigen::Index>(patchTriangles.size()));
  Eigen::Matrix3Xd frameDisplacement(3, patch.vertices.cols());
  const Eigen::Matrix3d toFrame = d.B.transpose() * d.R.transpose();  // Psi = B^T R^T d inverts eq. (1)'s R B
  for (std::size_t i = 0; i < patchVertices.size(); ++i) {
    const int v = patchVertices[i];
    patch.vertices.col(static_cast<Eigen::Index>(i)) = surface.vertices.col(v);
    frameDisplacement.col(static_cast<Eigen::Index>(i)) = toFrame * (result.fine.col(v) - result.coarseOnFine.col(v));
  }
  for (std::size_t f = 0; f < patchTriangles.size(); ++f) patch.triangles.col(static_cast<Eigen::Index>(f)) = patchTriangles[f];

  examples::Example e;
  e.contact = d.p;
  e.frame = d.B;
  e.rho = d.rho;
  e.mu = d.mu;
  e.stamp = enrichment::rasteriseStamp(patch, frameDisplacement, d.p, d.B, R, options_.stampResolution);
  e.stampRadius = R;
  e.pattern.indentDepth = entry.depth;
  e.pattern.drag = entry.drag;
  e.sceneId = "slab";
  examples::validateExample(e, "acquired example");
  return e;
}

examples::ExampleSet SlabAcquisition::acquireSet(const std::vector<PlanEntry>& plan, const std::string& directory, std::ostream* log) {
  examples::ExampleSet previous;
  if (std::filesystem::exists(std::filesystem::path(directory) / examples::kManifestFile)) {
    try {
      previous = examples::loadExampleSet(directory);
      if (log) *log << "resuming: " << previous.examples.size() << " examples already in " << directory << "\n";
    } catch (const std::exception& e) {
      if (log) *log << "existing set not reusable (" << e.what() << "), starting over\n";
    }
  }
  examples::ExampleSet set;
  set.metadata.scene = "slab";
  set.metadata.material = materialMetadata();
  set.metadata.description = "de_make_examples: coarse vs fine slab (cells and tool in the material metadata), SNH";
  const bool sameSetup = previous.metadata.material == set.metadata.material;
  for (std::size_t i = 0; i < plan.size(); ++i) {
    const PlanEntry& entry = plan[i];
    const auto done = std::find_if(previous.examples.begin(), previous.examples.end(), [&](const examples::Example& e) {
      return sameSetup && e.stamp.rows == options_.stampResolution && (e.contact - entry.point).norm() < 1e-9 &&
             std::abs(e.pattern.indentDepth - entry.depth) < 1e-12 && (e.pattern.drag - entry.drag).norm() < 1e-12;
    });
    if (done != previous.examples.end()) {
      set.examples.push_back(*done);
      if (log) *log << "[" << i + 1 << "/" << plan.size() << "] already acquired, skipped\n";
      continue;
    }
    const InteractionResult r = simulate(entry);
    if (!r.converged && log) *log << "  warning: " << r.message << "\n";
    set.examples.push_back(makeExample(entry, r));
    examples::saveExampleSet(set, directory);  // after every example: resumable
    if (log)
      *log << "[" << i + 1 << "/" << plan.size() << "] p = (" << entry.point.transpose() << "), depth " << entry.depth
           << ", drag (" << entry.drag.transpose() << "): coarse " << r.coarseSeconds << " s, fine " << r.fineSeconds
           << " s, max |d| " << (r.fine - r.coarseOnFine).cwiseAbs().maxCoeff() << " m" << std::endl;
  }
  examples::saveExampleSet(set, directory);
  return set;
}

std::string defaultExampleSetDirectory(const std::string& scene) {
  if (const char* cache = std::getenv("DE_EXAMPLE_CACHE"); cache && *cache) return (std::filesystem::path(cache) / scene).string();
  std::filesystem::path base;
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg) {
    base = xdg;
  } else if (const char* home = std::getenv("HOME"); home && *home) {
    base = std::filesystem::path(home) / ".cache";
  } else {
    throw IoError("defaultExampleSetDirectory: neither DE_EXAMPLE_CACHE, XDG_CACHE_HOME nor HOME is set");
  }
  return (base / "deformation_enrichment" / "example_sets" / scene).string();
}

}  // namespace deformation_enrichment::acquisition
