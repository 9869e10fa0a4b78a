#include "deformation_enrichment/descriptors/shell_sampling.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "deformation_enrichment/descriptors/sample_grid.hpp"
#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/surface_projection.hpp"

namespace deformation_enrichment::descriptors {
namespace {

// The surface's open rim: edges of one triangle, and their vertices.
struct Rim {
  std::map<std::pair<int, int>, int> edgeUses;
  std::vector<char> vertex;

  explicit Rim(const mesh::TriangleMesh& surface) : vertex(static_cast<std::size_t>(surface.numVertices()), 0) {
    for (Eigen::Index t = 0; t < surface.numTriangles(); ++t)
      for (int k = 0; k < 3; ++k) ++edgeUses[key(surface.triangles(k, t), surface.triangles((k + 1) % 3, t))];
    for (const auto& [edge, uses] : edgeUses)
      if (uses == 1) vertex[static_cast<std::size_t>(edge.first)] = vertex[static_cast<std::size_t>(edge.second)] = 1;
  }
  static std::pair<int, int> key(int a, int b) { return {std::min(a, b), std::max(a, b)}; }
  bool edge(int a, int b) const { return edgeUses.at(key(a, b)) == 1; }
};

// Whether the nearest surface point lies on the open rim (on a rim edge or at a rim vertex): cells whose
// nearest point is there lie beside the surface, not behind it.
bool onRim(const mesh::SurfacePoint& nearest, const mesh::TriangleMesh& surface, const Rim& rim) {
  const Eigen::Vector3i corners = surface.triangles.col(nearest.triangle);
  constexpr double kOn = 1e-9;
  int zeros = 0, opposite = -1, kept = -1;
  for (int k = 0; k < 3; ++k) {
    if (nearest.barycentric(k) <= kOn) {
      ++zeros;
      opposite = k;
    } else {
      kept = k;
    }
  }
  if (zeros == 2) return rim.vertex[static_cast<std::size_t>(corners(kept))] != 0;
  if (zeros == 1) return rim.edge(corners((opposite + 1) % 3), corners((opposite + 2) % 3));
  return false;
}

}  // namespace

PointSampling sampleShellUnderSurface(const mesh::TriangleMesh& surface, double thickness, double spacing, long maxSamples) {
  mesh::validate(surface, false);
  if (!(thickness > 0.0) || !std::isfinite(thickness))
    throw InvalidInputError("shell sampling: thickness must be positive, got " + std::to_string(thickness));
  // The surface's own grid (as sampleClosedSurfaceInterior's) grown by the thickness, so shell samples fall
  // where interior samples of the same object would.
  const SampleGrid inner = sampleGrid(surface.vertices.rowwise().minCoeff(), surface.vertices.rowwise().maxCoeff(), spacing,
                                      maxSamples, "shell sampling");
  const int extra = static_cast<int>(std::ceil(thickness / inner.step.minCoeff()));
  const SampleGrid grid = inner.grown(extra);
  if (grid.cells.cast<double>().prod() > static_cast<double>(maxSamples))
    throw InvalidInputError("shell sampling: spacing " + std::to_string(spacing) + " m and thickness " +
                            std::to_string(thickness) + " m give more than " + std::to_string(maxSamples) + " grid cells");
  // Candidates: cells within the thickness of some triangle's bounding box, so the nearest-point queries
  // cost the shell's size, not the box's.
  const auto index = [&](int i, int j, int k) {
    return static_cast<std::size_t>(i) + static_cast<std::size_t>(grid.cells[0]) * (j + static_cast<std::size_t>(grid.cells[1]) * k);
  };
  std::vector<char> candidate(static_cast<std::size_t>(grid.cells.cast<double>().prod()), 0);
  for (Eigen::Index t = 0; t < surface.numTriangles(); ++t) {
    Eigen::Vector3d lo = surface.vertices.col(surface.triangles(0, t)), hi = lo;
    for (int c = 1; c < 3; ++c) {
      lo = lo.cwiseMin(surface.vertices.col(surface.triangles(c, t)));
      hi = hi.cwiseMax(surface.vertices.col(surface.triangles(c, t)));
    }
    Eigen::Vector3i first, last;
    for (int axis = 0; axis < 3; ++axis) grid.centresWithin(axis, lo[axis] - thickness, hi[axis] + thickness, first[axis], last[axis]);
    for (int k = first.z(); k <= last.z(); ++k)
      for (int j = first.y(); j <= last.y(); ++j)
        for (int i = first.x(); i <= last.x(); ++i) candidate[index(i, j, k)] = 1;
  }
  const mesh::SurfaceProjector projector(surface);
  const Rim rim(surface);
  const double cone = std::cos(M_PI / 3.0);
  std::vector<Eigen::Vector3d> inside;
  for (int k = 0; k < grid.cells.z(); ++k)
    for (int j = 0; j < grid.cells.y(); ++j)
      for (int i = 0; i < grid.cells.x(); ++i) {
        if (!candidate[index(i, j, k)]) continue;
        const Eigen::Vector3d x = grid.centre(i, j, k);
        const mesh::SurfacePoint nearest = projector.project(x);
        if (nearest.distance > thickness || nearest.distance == 0.0) continue;
        if ((x - nearest.point).dot(nearest.normal) > -cone * nearest.distance) continue;  // not behind the surface
        if (!onRim(nearest, surface, rim)) inside.push_back(x);
      }
  if (inside.empty()) throw InvalidInputError("shell sampling: no grid cell centre lies in the shell under the surface");
  Eigen::Matrix3Xd points(3, static_cast<Eigen::Index>(inside.size()));
  for (std::size_t m = 0; m < inside.size(); ++m) points.col(static_cast<Eigen::Index>(m)) = inside[m];
  return PointSampling(std::move(points), Eigen::VectorXd::Constant(static_cast<Eigen::Index>(inside.size()), grid.cellVolume()));
}

}  // namespace deformation_enrichment::descriptors
