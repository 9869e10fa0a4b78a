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

// Display vertices a tool may touch: on the model's touchable boundary, two tool radii from the support, and
// where SceneAcquisition::toolPath accepts a press (both models' boundaries within the tool's reach).
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
    if (nearSupport) continue;
    PlanEntry press;
    press.point = x;
    try {
      acquisition.toolPath(press);
    } catch (const InvalidInputError&) {
      continue;
    }
    vertices.push_back(static_cast<int>(v));
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

// A third of the incident triangles' area for each candidate vertex: the surface a site stands for.
std::vector<double> vertexAreas(const mesh::TriangleMesh& surface, const std::vector<int>& candidates) {
  std::vector<double> perVertex(static_cast<std::size_t>(surface.numVertices()), 0.0);
  for (Eigen::Index f = 0; f < surface.numTriangles(); ++f) {
    const Eigen::Vector3i t = surface.triangles.col(f);
    const double third = (surface.vertices.col(t(1)) - surface.vertices.col(t(0)))
                             .cross(surface.vertices.col(t(2)) - surface.vertices.col(t(0)))
                             .norm() / 6.0;
    for (int k = 0; k < 3; ++k) perVertex[static_cast<std::size_t>(t(k))] += third;
  }
  std::vector<double> areas;
  for (int v : candidates) areas.push_back(perVertex[static_cast<std::size_t>(v)]);
  return areas;
}

// Sites per region in proportion to the region's area (largest remainders), at least one each.
std::vector<int> sitesPerRegion(const std::vector<int>& labels, const std::vector<double>& areas, int regions, int sites) {
  std::vector<double> regionArea(static_cast<std::size_t>(regions), 0.0);
  for (std::size_t k = 0; k < labels.size(); ++k) regionArea[static_cast<std::size_t>(labels[k])] += areas[k];
  double total = 0.0;
  for (double a : regionArea) total += a;
  std::vector<int> count(static_cast<std::size_t>(regions), 1);
  std::vector<double> share(static_cast<std::size_t>(regions));
  for (int r = 0; r < regions; ++r) share[static_cast<std::size_t>(r)] = (sites - regions) * regionArea[static_cast<std::size_t>(r)] / total;
  int left = sites - regions;
  for (int r = 0; r < regions; ++r) {
    const int whole = static_cast<int>(std::floor(share[static_cast<std::size_t>(r)]));
    count[static_cast<std::size_t>(r)] += whole;
    share[static_cast<std::size_t>(r)] -= whole;
    left -= whole;
  }
  for (; left > 0; --left) {  // largest remainder first; ties to the lower region id
    const auto largest = std::max_element(share.begin(), share.end()) - share.begin();
    ++count[static_cast<std::size_t>(largest)];
    share[static_cast<std::size_t>(largest)] = -1.0;
  }
  return count;
}

// `count` sites of a region: the vertex whose rho is nearest the region's mean, then each next one the
// region's vertex farthest (in space) from the sites chosen so far.
std::vector<std::size_t> spreadSites(const descriptors::KMeansResult& clusters, const std::vector<hermite::MomentList>& rho,
                                     const mesh::TriangleMesh& surface, const std::vector<int>& candidates, int region,
                                     int count) {
  std::vector<std::size_t> members;
  for (std::size_t k = 0; k < candidates.size(); ++k)
    if (clusters.labels[k] == region) members.push_back(k);
  std::vector<std::size_t> chosen;
  double best = INFINITY;
  for (std::size_t k : members) {
    const double d = descriptors::siteDistance(rho[k], clusters.centres[static_cast<std::size_t>(region)]);
    if (d < best) best = d, chosen.assign(1, k);
  }
  std::vector<double> nearest(members.size(), INFINITY);
  while (static_cast<int>(chosen.size()) < std::min<int>(count, static_cast<int>(members.size()))) {
    const Eigen::Vector3d last = surface.vertices.col(candidates[chosen.back()]);
    std::size_t farthest = 0;
    for (std::size_t m = 0; m < members.size(); ++m) {
      nearest[m] = std::min(nearest[m], (surface.vertices.col(candidates[members[m]]) - last).norm());
      if (nearest[m] > nearest[farthest]) farthest = m;
    }
    chosen.push_back(members[farthest]);
  }
  return chosen;
}

}  // namespace

std::vector<PlanEntry> autoPlan(SceneAcquisition& acquisition, int examples) {
  if (examples < 1) throw InvalidInputError("autoPlan: needs at least one example, got " + std::to_string(examples));
  const std::vector<int> candidates = touchableSurfaceVertices(acquisition);
  const int sites = (examples + kPatternsPerSite - 1) / kPatternsPerSite;
  const int regions = std::min(sites, kMaxRegions);
  if (static_cast<int>(candidates.size()) < sites)
    throw InvalidInputError("autoPlan: " + std::to_string(candidates.size()) + " touchable surface vertices for " +
                            std::to_string(sites) + " sites");
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
  const std::vector<int> perRegion = sitesPerRegion(clusters.labels, vertexAreas(surface, candidates), regions, sites);
  const double r = acquisition.scene().tool.radius;
  std::vector<PlanEntry> plan;
  for (int region = 0; region < regions; ++region) {
    for (const std::size_t site : spreadSites(clusters, rho, surface, candidates, region, perRegion[static_cast<std::size_t>(region)])) {
      const Eigen::Vector3d p = surface.vertices.col(candidates[site]);
      const Eigen::Matrix3d& B = frames[site];
      const Eigen::Vector3d drags[kPatternsPerSite] = {Eigen::Vector3d::Zero(), r * B.col(0), r * B.col(1)};
      for (int pattern = 0; pattern < kPatternsPerSite && static_cast<int>(plan.size()) < examples; ++pattern)
        plan.push_back(pressAt(p, r, drags[pattern]));
    }
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
