#include "deformation_enrichment/acquisition/plan_generation.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <random>

#include "deformation_enrichment/descriptors/descriptor_distance.hpp"
#include "deformation_enrichment/descriptors/site_segmentation.hpp"
#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::acquisition {
namespace {

// Display vertices a tool may touch: on the model's touchable boundary and two tool radii from the support.
std::vector<int> touchableSurfaceVertices(const SceneAcquisition& acquisition) {
  const scenes::SceneModels& m = acquisition.models();
  const double keep = 2.0 * acquisition.scene().tool.radius;
  std::vector<char> top(static_cast<std::size_t>(m.fine.mesh.numVertices()), 0);
  for (int v : m.fine.topVertices) top[static_cast<std::size_t>(v)] = 1;
  std::vector<int> vertices;
  for (Eigen::Index v = 0; v < m.surface.numVertices(); ++v) {
    const int fine = m.surfaceToFine[static_cast<std::size_t>(v)];
    if (!top[static_cast<std::size_t>(fine)]) continue;
    const Eigen::Vector3d x = m.surface.vertices.col(v);
    const bool nearSupport = std::any_of(m.fine.fixedVertices.begin(), m.fine.fixedVertices.end(),
                                         [&](int f) { return (m.fine.mesh.vertices.col(f) - x).norm() < keep; });
    if (!nearSupport) vertices.push_back(static_cast<int>(v));
  }
  return vertices;
}

PlanEntry pressAt(const Eigen::Vector3d& point, double radius, const Eigen::Vector3d& drag) {
  PlanEntry e;
  e.point = point;
  e.depth = 0.6 * radius;
  e.drag = drag;
  return e;
}

}  // namespace

std::vector<PlanEntry> autoPlan(SceneAcquisition& acquisition, int examples) {
  if (examples < 1) throw InvalidInputError("autoPlan: needs at least one example, got " + std::to_string(examples));
  const std::vector<int> candidates = touchableSurfaceVertices(acquisition);
  const int regions = (examples + kPatternsPerSite - 1) / kPatternsPerSite;
  if (static_cast<int>(candidates.size()) < regions)
    throw InvalidInputError("autoPlan: " + std::to_string(candidates.size()) + " touchable surface vertices for " +
                            std::to_string(regions) + " site regions");
  // Site descriptors in each vertex's stamping frame at rest, as the examples will be described.
  const mesh::TriangleMesh& surface = acquisition.fineSurface();
  std::vector<hermite::MomentList> rho;
  std::vector<Eigen::Matrix3d> frames;
  for (int v : candidates) {
    enrichment::Contact c;
    c.point = surface.vertices.col(v);
    const enrichment::ContactDescription d = acquisition.enricher().describe(surface.vertices, c);
    rho.push_back(d.rho);
    frames.push_back(d.B);
  }
  descriptors::KMeansOptions kmeans;
  kmeans.clusters = regions;
  const descriptors::KMeansResult clusters = descriptors::kMeansSites(rho, kmeans);
  const double r = acquisition.scene().tool.radius;
  std::vector<PlanEntry> plan;
  for (int region = 0; region < regions; ++region) {
    std::size_t site = 0;
    double best = INFINITY;
    for (std::size_t k = 0; k < candidates.size(); ++k) {
      if (clusters.labels[k] != region) continue;
      const double d = descriptors::siteDistance(rho[k], clusters.centres[static_cast<std::size_t>(region)]);
      if (d < best) best = d, site = k;
    }
    const Eigen::Vector3d p = surface.vertices.col(candidates[site]);
    const Eigen::Matrix3d& B = frames[site];
    const Eigen::Vector3d drags[kPatternsPerSite] = {Eigen::Vector3d::Zero(), r * B.col(0), r * B.col(1)};
    for (int pattern = 0; pattern < kPatternsPerSite && static_cast<int>(plan.size()) < examples; ++pattern)
      plan.push_back(pressAt(p, r, drags[pattern]));
  }
  return plan;
}

std::vector<PlanEntry> randomContacts(const SceneAcquisition& acquisition, int count, unsigned seed) {
  if (count < 1) throw InvalidInputError("randomContacts: needs at least one contact");
  const std::vector<int> vertices = touchableSurfaceVertices(acquisition);
  const mesh::TriangleMesh& surface = acquisition.fineSurface();
  std::vector<char> touchable(static_cast<std::size_t>(surface.numVertices()), 0);
  for (int v : vertices) touchable[static_cast<std::size_t>(v)] = 1;
  std::vector<Eigen::Index> triangles;
  std::vector<double> areas;
  for (Eigen::Index f = 0; f < surface.numTriangles(); ++f) {
    const Eigen::Vector3i t = surface.triangles.col(f);
    if (!touchable[static_cast<std::size_t>(t(0))] || !touchable[static_cast<std::size_t>(t(1))] ||
        !touchable[static_cast<std::size_t>(t(2))])
      continue;
    triangles.push_back(f);
    areas.push_back(0.5 * (surface.vertices.col(t(1)) - surface.vertices.col(t(0)))
                              .cross(surface.vertices.col(t(2)) - surface.vertices.col(t(0)))
                              .norm());
  }
  if (triangles.empty()) throw InvalidInputError("randomContacts: no touchable surface away from the support");
  std::mt19937 rng(seed);
  std::discrete_distribution<std::size_t> pick(areas.begin(), areas.end());
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double r = acquisition.scene().tool.radius;
  std::vector<PlanEntry> contacts;
  for (int k = 0; k < count; ++k) {
    const Eigen::Vector3i t = surface.triangles.col(triangles[pick(rng)]);
    double a = unit(rng), b = unit(rng);
    if (a + b > 1.0) a = 1.0 - a, b = 1.0 - b;  // uniform over the triangle
    const Eigen::Vector3d x0 = surface.vertices.col(t(0)), x1 = surface.vertices.col(t(1)), x2 = surface.vertices.col(t(2));
    PlanEntry e;
    e.point = x0 + a * (x1 - x0) + b * (x2 - x0);
    e.depth = r * (0.4 + 0.4 * unit(rng));
    if (k % 2 == 1) {
      const Eigen::Vector3d n = (x1 - x0).cross(x2 - x0).normalized();
      const Eigen::Vector3d u = (x1 - x0).normalized(), w = n.cross(u);
      const double angle = 2.0 * M_PI * unit(rng), length = r * (0.2 + 0.8 * unit(rng));
      e.drag = length * (std::cos(angle) * u + std::sin(angle) * w);
    }
    contacts.push_back(e);
  }
  return contacts;
}

}  // namespace deformation_enrichment::acquisition
