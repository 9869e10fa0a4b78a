#include "deformation_enrichment/acquisition/scene_acquisition.hpp"

#include <Eigen/Geometry>
#include <chrono>
#include <cmath>
#include <functional>

#include "deformation_enrichment/acquisition/tool_loading.hpp"
#include "deformation_enrichment/elasticity/quasi_static_solver.hpp"
#include "deformation_enrichment/elasticity/tet_fem.hpp"
#include "deformation_enrichment/enrichment/example_set_options.hpp"
#include "deformation_enrichment/enrichment/stamp.hpp"
#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/barycentric_embedding.hpp"
#include "deformation_enrichment/mesh/embedded_state_fit.hpp"
#include "deformation_enrichment/mesh/surface_projection.hpp"
#include "deformation_enrichment/mesh/tet_surface.hpp"
#include "deformation_enrichment/seconds_since.hpp"

namespace deformation_enrichment::acquisition {
namespace {

using Clock = std::chrono::steady_clock;
using scene_file::SceneDescription;
using scene_file::ToolModel;

// One model (coarse or fine) with its finite elements and its own boundary: a coarse volume around an
// embedded display surface has its boundary up to a few millimetres away from it, and the tool loads each
// model where the tool meets that model's boundary.
struct Body {
  const scenes::Scene* scene = nullptr;
  std::unique_ptr<elasticity::TetFem> fem;
  std::unique_ptr<mesh::SurfaceProjector> boundary;
};

Body makeBody(const scenes::Scene& scene, const SceneDescription& d, double skinYoung) {
  const auto bulk = elasticity::lameFromYoungPoisson(d.material.young, d.material.poisson);
  const auto skin = d.skin ? elasticity::lameFromYoungPoisson(skinYoung, d.skin->material.poisson) : bulk;
  Body body;
  body.scene = &scene;
  body.fem = std::make_unique<elasticity::TetFem>(
      scene.mesh,
      std::vector<elasticity::StableNeoHookean>{elasticity::StableNeoHookean(bulk.mu, bulk.lambda),
                                                elasticity::StableNeoHookean(skin.mu, skin.lambda)},
      scene.materialId);
  body.boundary = std::make_unique<mesh::SurfaceProjector>(mesh::extractSurface(scene.mesh).surface);
  return body;
}

// Dirichlet tool: the touchable vertices within the tool radius of the contact, or the nearest one when the
// model is too coarse to have any there.
std::vector<int> dirichletTool(const scenes::Scene& scene, const Eigen::Vector3d& contact, double radius) {
  std::vector<int> tool = scenes::verticesNear(scene.mesh, scene.topVertices, contact, radius);
  if (!tool.empty()) return tool;
  int nearest = -1;
  double best = INFINITY;
  for (int v : scene.topVertices) {
    const double distance = (scene.mesh.vertices.col(v) - contact).norm();
    if (distance < best) best = distance, nearest = v;
  }
  if (nearest < 0) throw InvalidInputError("acquisition: the scene has no touchable vertex");
  return {nearest};
}

// Quasi-static path: indent along the inward normal in `indentSteps`, then drag in `dragSteps`; `onStep`
// (optional) sees the positions after every step. Returns seconds.
double solvePath(const Body& body, const ToolPath& path, const SceneDescription& d, int indentSteps, int dragSteps,
                 Eigen::Matrix3Xd& positions, bool& converged, std::string& message,
                 const std::function<void(const Eigen::Matrix3Xd&)>& onStep = {}) {
  const auto start = Clock::now();
  const scenes::Scene& scene = *body.scene;
  const Eigen::Vector3d contact = body.boundary->project(path.contact).point;
  std::vector<int> tool;
  elasticity::AnchorSprings springs;
  Eigen::Matrix3Xd springRest;
  if (d.tool.model == ToolModel::Dirichlet) {
    tool = dirichletTool(scene, contact, d.tool.radius);
  } else {
    springs = acquisition::toolSprings(scene, contact, d.tool.radius, d.tool.stiffness);
    springRest = springs.targets;
  }
  const double dragDistance = path.drag.norm();
  if (dragDistance == 0.0) dragSteps = 0;
  const Eigen::Vector3d dragDirection = dragDistance > 0.0 ? Eigen::Vector3d(path.drag / dragDistance) : Eigen::Vector3d::UnitX();
  elasticity::SolverOptions settings;
  settings.relativeForceTolerance = d.solve.relativeTolerance;
  elasticity::QuasiStaticSolver solver(*body.fem, settings);
  positions = scene.mesh.vertices;
  for (int step = 1; step <= indentSteps + dragSteps; ++step) {
    const Eigen::Vector3d u =
        acquisition::toolDisplacement(step, indentSteps, dragSteps, path.inward, path.depth, dragDirection, dragDistance);
    elasticity::SolveResult r;
    if (d.tool.model == ToolModel::Dirichlet) {
      r = solver.solve(positions, acquisition::toolConstraints(scene, tool, u));
    } else {
      springs.targets = springRest.colwise() + u;
      r = solver.solve(positions, acquisition::supportConstraints(scene), springs);
    }
    if (!r.converged()) {
      converged = false;
      message += "step " + std::to_string(step) + ": " + r.message + "; ";
    }
    if (onStep) onStep(positions);
  }
  return secondsSince(start);
}

void checkEntry(const PlanEntry& entry) {
  if (!entry.point.allFinite() || !entry.drag.allFinite() || !std::isfinite(entry.depth) || entry.depth < 0.0)
    throw InvalidInputError("acquisition: non-finite interaction or negative depth");
}

}  // namespace

enrichment::ContactEnricherOptions enricherOptions(const SceneDescription& scene) {
  return enrichment::optionsFor(scene, enrichment::ContactEnricherOptions());
}

struct SceneAcquisition::Impl {
  scenes::SceneModels models;
  Body coarse, fine;
  mesh::BarycentricEmbedding embedding;
  mesh::SurfaceProjector projector;
  std::vector<char> fixedSurfaceVertex;
  std::unique_ptr<enrichment::ContactEnricher> enricher;

  explicit Impl(scenes::SceneModels m) : models(std::move(m)), projector(models.surface) {}
};

SceneAcquisition::SceneAcquisition(SceneDescription scene) : scene_(std::move(scene)) {
  impl_ = std::make_unique<Impl>(scenes::buildSceneModels(scene_));
  const double skinYoung = scene_.skin ? scene_.skin->material.young : scene_.material.young;
  impl_->coarse = makeBody(impl_->models.coarse, scene_, scene_.coarseSkinYoung.value_or(skinYoung));
  impl_->fine = makeBody(impl_->models.fine, scene_, skinYoung);
  // Display vertices slightly outside the coarse volume get the nearest tet's affine extension.
  impl_->embedding = mesh::embedPoints(impl_->models.coarse.mesh, impl_->models.surface.vertices, scene_.maxOutside);
  impl_->fixedSurfaceVertex.assign(static_cast<std::size_t>(impl_->models.fine.mesh.numVertices()), 0);
  for (int v : impl_->models.fine.fixedVertices) impl_->fixedSurfaceVertex[static_cast<std::size_t>(v)] = 1;
  impl_->enricher = std::make_unique<enrichment::ContactEnricher>(impl_->models.surface, enricherOptions(scene_));
}

SceneAcquisition::~SceneAcquisition() = default;

const scenes::SceneModels& SceneAcquisition::models() const { return impl_->models; }
const mesh::TriangleMesh& SceneAcquisition::fineSurface() const { return impl_->models.surface; }
enrichment::ContactEnricher& SceneAcquisition::enricher() { return *impl_->enricher; }

std::pair<long, double> SceneAcquisition::outsideVertices() const {
  const Eigen::VectorXd& outside = impl_->embedding.outside;
  return {static_cast<long>((outside.array() > 0.0).count()), outside.size() ? outside.maxCoeff() : 0.0};
}

ToolPath SceneAcquisition::toolPath(const PlanEntry& entry) const {
  checkEntry(entry);
  const mesh::SurfacePoint s = impl_->projector.project(entry.point);
  const auto point = [&] {
    return "(" + std::to_string(entry.point.x()) + ", " + std::to_string(entry.point.y()) + ", " + std::to_string(entry.point.z()) + ")";
  };
  if (s.distance > scene_.stamp.radius)
    throw InvalidInputError(scene_.path + ": plan point " + point() + " is " + std::to_string(s.distance) +
                            " m from the surface, farther than the stamp radius " + std::to_string(scene_.stamp.radius) + " m");
  const Eigen::Vector3i t = impl_->models.surface.triangles.col(s.triangle);
  bool held = true;
  for (int k = 0; k < 3; ++k)
    held = held && impl_->fixedSurfaceVertex[static_cast<std::size_t>(impl_->models.surfaceToFine[static_cast<std::size_t>(t(k))])];
  if (held) throw InvalidInputError(scene_.path + ": plan point " + point() + " lands on the fixed region");
  // The tool loads each model at its own boundary, which for an embedded display surface lies apart from it.
  for (const Body* body : {&impl_->coarse, &impl_->fine}) {
    const double gap = body->boundary->project(s.point).distance;
    if (gap > scene_.tool.radius)
      throw InvalidInputError(scene_.path + ": at plan point " + point() + " the " + (body == &impl_->coarse ? "coarse" : "fine") +
                              " model's boundary is " + std::to_string(gap * 1e3) + " mm from the display surface, farther than the "
                              "tool radius " + std::to_string(scene_.tool.radius * 1e3) + " mm");
  }
  ToolPath path;
  path.contact = s.point;
  path.inward = -s.normal;
  path.depth = entry.depth;
  path.drag = entry.drag - entry.drag.dot(s.normal) * s.normal;  // tangential part
  return path;
}

std::vector<Eigen::Vector3d> SceneAcquisition::toolCentres(const PlanEntry& entry) const {
  const ToolPath path = toolPath(entry);
  const Eigen::Vector3d touching = path.contact - scene_.tool.radius * path.inward;
  const double drag = path.drag.norm();
  const int indentSteps = scene_.solve.indentSteps, dragSteps = drag > 0.0 ? scene_.solve.dragSteps : 0;
  const Eigen::Vector3d dragDirection = drag > 0.0 ? Eigen::Vector3d(path.drag / drag) : Eigen::Vector3d::UnitX();
  std::vector<Eigen::Vector3d> centres;
  for (int step = 0; step <= indentSteps + dragSteps; ++step)
    centres.push_back(touching + toolDisplacement(step, indentSteps, dragSteps, path.inward, path.depth, dragDirection, drag));
  return centres;
}

enrichment::Contact SceneAcquisition::contactOf(const PlanEntry& entry) const {
  enrichment::Contact c;
  c.point = toolPath(entry).contact;
  return c;
}

InteractionResult SceneAcquisition::simulate(const PlanEntry& entry) const {
  const ToolPath path = toolPath(entry);
  InteractionResult r;
  Eigen::Matrix3Xd coarse;
  r.coarseSeconds = solvePath(impl_->coarse, path, scene_, scene_.solve.indentSteps, scene_.solve.dragSteps, coarse, r.converged, r.message);
  r.coarseOnFine = coarseOnFineSurface(coarse);
  r.coarseNodes = coarse;
  solveFine(path, r);
  return r;
}

InteractionResult SceneAcquisition::simulate(const PlanEntry& entry, const Eigen::Matrix3Xd& coarseOnSurface) const {
  const ToolPath path = toolPath(entry);
  const scenes::SceneModels& m = impl_->models;
  if (coarseOnSurface.cols() != m.surface.numVertices())
    throw InvalidInputError("acquisition: a coarse state of " + std::to_string(coarseOnSurface.cols()) + " points for a display surface of " +
                            std::to_string(m.surface.numVertices()) + " vertices");
  if (!coarseOnSurface.allFinite()) throw InvalidInputError("acquisition: the given coarse state is not finite");
  InteractionResult r;
  r.coarseOnFine = coarseOnSurface;
  const mesh::TetMesh& rest = m.coarse.mesh;
  r.coarseNodes = rest.vertices + mesh::fitNodeDisplacements(rest, impl_->embedding, coarseOnSurface - m.surface.vertices, m.coarse.fixedVertices);
  solveFine(path, r);
  return r;
}

void SceneAcquisition::solveFine(const ToolPath& path, InteractionResult& r) const {
  Eigen::Matrix3Xd fine;
  r.fineSeconds = solvePath(impl_->fine, path, scene_, scene_.solve.indentSteps, scene_.solve.dragSteps, fine, r.converged, r.message);
  r.fineNodes = fine;
  r.fine = fineOnSurface(fine);
}

Eigen::Matrix3Xd SceneAcquisition::fineOnSurface(const Eigen::Matrix3Xd& fine) const {
  const scenes::SceneModels& m = impl_->models;
  if (m.surfaceOnFine) return mesh::interpolate(*m.surfaceOnFine, m.fine.mesh, fine);  // positions: barycentric weights sum to one
  Eigen::Matrix3Xd onSurface(3, m.surface.numVertices());
  for (Eigen::Index v = 0; v < onSurface.cols(); ++v) onSurface.col(v) = fine.col(m.surfaceToFine[static_cast<std::size_t>(v)]);
  return onSurface;
}

cv::Mat SceneAcquisition::volumeStamp(const InteractionResult& result, const Eigen::Vector3d& p, const Eigen::Matrix3d& B,
                                      const Eigen::Matrix3d& toFrame) const {
  const int n = scene_.stamp.resolution, layers = scene_.stamp.layers;
  const double R = scene_.stamp.radius;
  if (result.fineNodes.cols() != impl_->models.fine.mesh.numVertices() || result.coarseNodes.cols() != impl_->models.coarse.mesh.numVertices())
    throw InvalidInputError("volume stamp: the interaction result holds no volume states of this scene's models");
  const Eigen::Matrix3Xd nodes = enrichment::volumeStampNodes(p, B, R, n, layers);
  // Nodes within one grid step outside a model take its nearest tet's affine extension (as display vertices
  // outside the coarse volume do); farther out, in the air, the nearest node inside gives its value.
  const double step = 2.0 * R / std::min(n - 1, layers - 1);
  const mesh::TetMesh& fine = impl_->models.fine.mesh;
  const mesh::TetMesh& coarse = impl_->models.coarse.mesh;
  const mesh::BarycentricEmbedding inFine = mesh::embedPoints(fine, nodes, step, mesh::FarPoints::Skip);
  const mesh::BarycentricEmbedding inCoarse = mesh::embedPoints(coarse, nodes, step + scene_.maxOutside, mesh::FarPoints::Skip);
  const Eigen::Matrix3Xd difference = mesh::interpolate(inFine, fine, result.fineNodes - fine.vertices) -
                                      mesh::interpolate(inCoarse, coarse, result.coarseNodes - coarse.vertices);
  std::vector<char> known(static_cast<std::size_t>(nodes.cols()));
  for (Eigen::Index i = 0; i < nodes.cols(); ++i) known[static_cast<std::size_t>(i)] = inFine.tet[i] >= 0 && inCoarse.tet[i] >= 0;
  return enrichment::volumeStampFromNodes(toFrame * difference, known, n, layers);
}

Eigen::Matrix3Xd SceneAcquisition::coarseOnFineSurface(const Eigen::Matrix3Xd& coarse) const {
  // The coarse displacement carried onto the display surface (exact for the coarse tets' affine fields).
  const mesh::TetMesh& rest = impl_->models.coarse.mesh;
  return impl_->models.surface.vertices + mesh::interpolate(impl_->embedding, rest, coarse - rest.vertices);
}

std::vector<Eigen::Matrix3Xd> SceneAcquisition::surfacePath(Resolution model, const PlanEntry& entry, int indentSteps,
                                                            int dragSteps, std::string* message) const {
  if (indentSteps < 1 || dragSteps < 0) throw InvalidInputError("surfacePath: needs indentSteps >= 1 and dragSteps >= 0");
  const ToolPath path = toolPath(entry);
  std::vector<Eigen::Matrix3Xd> states{impl_->models.surface.vertices};
  Eigen::Matrix3Xd positions;
  bool converged = true;
  std::string log;
  const bool coarse = model == Resolution::Coarse;
  solvePath(coarse ? impl_->coarse : impl_->fine, path, scene_, indentSteps, dragSteps, positions, converged, log,
            [&](const Eigen::Matrix3Xd& p) { states.push_back(coarse ? coarseOnFineSurface(p) : fineOnSurface(p)); });
  if (message) *message = log;
  return states;
}

examples::Example SceneAcquisition::makeExample(const PlanEntry& entry, const InteractionResult& result) {
  const ToolPath path = toolPath(entry);
  enrichment::Contact contact;
  contact.point = path.contact;
  const enrichment::ContactDescription d = impl_->enricher->describe(result.coarseOnFine, contact);
  const double R = scene_.stamp.radius;
  examples::Example e;
  e.contact = d.p;
  e.frame = d.B;
  e.rho = d.rho;
  e.mu = d.mu;
  // Psi = B^T R^T (fine - coarse) inverts eq. (1)'s R B: of the volume around the contact (a volume stamp),
  // or rasterised over the surface patch facing b_z (the paper's surface stamp).
  const Eigen::Matrix3d toFrame = d.B.transpose() * d.R.transpose();
  e.stamp = scene_.stamp.layers > 1 ? volumeStamp(result, d.p, d.B, toFrame)
                                    : enrichment::rasteriseFacingPatch(impl_->models.surface, result.fine - result.coarseOnFine, d.p,
                                                                       toFrame, d.B, R, scene_.stamp.resolution, impl_->models.fineEdge);
  e.stampRadius = R;
  e.stampLayers = scene_.stamp.layers;
  e.pattern.indentDepth = path.depth;
  e.pattern.drag = path.drag;
  e.sceneId = scene_.name;
  examples::validateExample(e, "acquired example");
  return e;
}

}  // namespace deformation_enrichment::acquisition
