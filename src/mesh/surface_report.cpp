#include "deformation_enrichment/mesh/surface_report.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <map>
#include <numeric>
#include <utility>
#include <vector>

#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::mesh {
namespace {

Eigen::Index countDuplicates(const Eigen::Matrix3Xd& vertices) {
  std::vector<Eigen::Index> order(static_cast<size_t>(vertices.cols()));
  std::iota(order.begin(), order.end(), Eigen::Index(0));
  const auto less = [&](Eigen::Index a, Eigen::Index b) {
    return std::lexicographical_compare(vertices.col(a).data(), vertices.col(a).data() + 3, vertices.col(b).data(),
                                        vertices.col(b).data() + 3);
  };
  std::sort(order.begin(), order.end(), less);
  Eigen::Index duplicates = 0;
  for (size_t k = 1; k < order.size(); ++k)
    if (vertices.col(order[k]) == vertices.col(order[k - 1])) ++duplicates;
  return duplicates;
}

bool degenerate(const TriangleMesh& mesh, const Eigen::Vector3i& tri) {
  if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2]) return true;
  const Eigen::Vector3d a = mesh.vertices.col(tri[1]) - mesh.vertices.col(tri[0]);
  const Eigen::Vector3d b = mesh.vertices.col(tri[2]) - mesh.vertices.col(tri[0]);
  return !(a.cross(b).norm() > 1e-12 * std::max(a.squaredNorm(), b.squaredNorm()));
}

}  // namespace

SurfaceReport inspectSurface(const TriangleMesh& mesh) {
  SurfaceReport report;
  report.vertices = mesh.numVertices();
  report.triangles = mesh.numTriangles();
  report.duplicateVertices = countDuplicates(mesh.vertices);
  std::vector<bool> used(static_cast<size_t>(mesh.numVertices()), false);
  // Per undirected edge (low, high): how many triangles use it in each direction.
  std::map<std::pair<int, int>, std::pair<int, int>> edges;
  for (Eigen::Index t = 0; t < mesh.numTriangles(); ++t) {
    const Eigen::Vector3i tri = mesh.triangles.col(t);
    for (int k = 0; k < 3; ++k) {
      if (tri[k] < 0 || tri[k] >= mesh.numVertices())
        throw InvalidInputError("inspectSurface: triangle " + std::to_string(t) + " references vertex " +
                                std::to_string(tri[k]) + " of " + std::to_string(mesh.numVertices()));
      used[static_cast<size_t>(tri[k])] = true;
    }
    if (degenerate(mesh, tri)) {
      ++report.degenerateTriangles;
      continue;
    }
    for (int k = 0; k < 3; ++k) {
      const int a = tri[k], b = tri[(k + 1) % 3];
      auto& uses = edges[{std::min(a, b), std::max(a, b)}];
      (a < b ? uses.first : uses.second) += 1;
    }
  }
  report.unusedVertices = std::count(used.begin(), used.end(), false);
  for (const auto& [edge, uses] : edges) {
    const int total = uses.first + uses.second;
    if (total == 1) ++report.boundaryEdges;
    if (total > 2) ++report.nonManifoldEdges;
    if (total == 2 && uses.first != 1) ++report.misorientedEdges;
  }
  return report;
}

std::string describe(const SurfaceReport& report) {
  std::string text = std::to_string(report.vertices) + " vertices, " + std::to_string(report.triangles) + " triangles, ";
  if (report.closedManifold()) text += "closed manifold";
  else text += report.boundaryEdges == 0 ? "closed" : std::to_string(report.boundaryEdges) + " boundary edges";
  const std::pair<Eigen::Index, const char*> counts[] = {{report.nonManifoldEdges, "non-manifold edges"},
                                                         {report.misorientedEdges, "inconsistently oriented edges"},
                                                         {report.duplicateVertices, "duplicate vertices"},
                                                         {report.unusedVertices, "unused vertices"},
                                                         {report.degenerateTriangles, "zero-area triangles"}};
  for (const auto& [count, what] : counts)
    if (count > 0) text += ", " + std::to_string(count) + " " + what;
  return text;
}

}  // namespace deformation_enrichment::mesh
