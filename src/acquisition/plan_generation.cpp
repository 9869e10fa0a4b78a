#include "deformation_enrichment/acquisition/plan_generation.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <random>

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

// The radical inverse of `index` in `base` (the Halton sequence's coordinate [Halton60]): 1/2, 1/4, 3/4, ...
double radicalInverse(int index, int base) {
  double result = 0.0, digit = 1.0 / base;
  for (; index > 0; index /= base, digit /= base) result += digit * (index % base);
  return result;
}

// Touchable vertices in farthest-point order, `count` of them: the one nearest the centroid first, then each
// the farthest (in space) from those chosen so far. A prefix of a longer order is the shorter order.
std::vector<int> farthestPointSites(const Eigen::Matrix3Xd& vertices, const std::vector<int>& candidates, int count) {
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (int v : candidates) centroid += vertices.col(v) / static_cast<double>(candidates.size());
  std::vector<double> nearest(candidates.size());
  for (std::size_t k = 0; k < candidates.size(); ++k) nearest[k] = -(vertices.col(candidates[k]) - centroid).norm();
  std::vector<int> sites;
  while (static_cast<int>(sites.size()) < count) {
    // First candidate of the largest distance (or of the smallest distance to the centroid, negated).
    const std::size_t next = static_cast<std::size_t>(std::max_element(nearest.begin(), nearest.end()) - nearest.begin());
    sites.push_back(candidates[next]);
    const Eigen::Vector3d x = vertices.col(candidates[next]);
    for (std::size_t k = 0; k < candidates.size(); ++k) {
      const double d = (vertices.col(candidates[k]) - x).norm();
      nearest[k] = sites.size() == 1 ? d : std::min(nearest[k], d);
    }
  }
  return sites;
}

}  // namespace

std::vector<PlanEntry> scenePlan(SceneAcquisition& acquisition, std::optional<int> examples) {
  const std::string& csv = acquisition.scene().plan;
  if (csv == "auto") return autoPlan(acquisition, examples.value_or(kDefaultAutoPlanSize));
  std::vector<PlanEntry> plan = readPlan(csv);
  if (examples && *examples > static_cast<int>(plan.size()))
    throw InvalidInputError("--examples " + std::to_string(*examples) + ": the plan " + csv + " has only " +
                            std::to_string(plan.size()) + " interactions");
  if (examples) plan.resize(static_cast<std::size_t>(*examples));
  return plan;
}

std::vector<PlanEntry> autoPlan(SceneAcquisition& acquisition, int examples) {
  if (examples < 1) throw InvalidInputError("autoPlan: needs at least one example, got " + std::to_string(examples));
  const std::vector<int> candidates = touchableSurfaceVertices(acquisition);
  if (static_cast<int>(candidates.size()) < examples)
    throw InvalidInputError("autoPlan: " + std::to_string(candidates.size()) + " touchable surface vertices for " +
                            std::to_string(examples) + " interactions");
  const mesh::TriangleMesh& surface = acquisition.fineSurface();
  const double r = acquisition.scene().tool.radius;
  std::vector<PlanEntry> plan;
  for (const int site : farthestPointSites(surface.vertices, candidates, examples)) {
    const int i = static_cast<int>(plan.size());
    PlanEntry e;
    e.point = surface.vertices.col(site);
    e.depth = r * (0.3 + 0.6 * radicalInverse(i + 1, 2));
    if (i % 2 == 1) {  // drags in the site's rest stamping frame, so they cover every direction relative to B
      enrichment::Contact c;
      c.point = e.point;
      const Eigen::Matrix3d B = acquisition.enricher().describe(surface.vertices, c).B;
      const int k = i / 2 + 1;
      const double length = r * (0.2 + 0.8 * radicalInverse(k, 3)), angle = 2.0 * M_PI * radicalInverse(k, 5);
      e.drag = length * (std::cos(angle) * B.col(0) + std::sin(angle) * B.col(1));
    }
    plan.push_back(e);
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
