#include "deformation_enrichment/descriptors/interior_sampling.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::descriptors {

PointSampling sampleClosedSurfaceInterior(const mesh::TriangleMesh& surface, double spacing, long maxSamples) {
  mesh::validate(surface, false);
  if (!(spacing > 0.0) || !std::isfinite(spacing))
    throw InvalidInputError("interior sampling: spacing must be positive, got " + std::to_string(spacing));
  const Eigen::Vector3d lo = surface.vertices.rowwise().minCoeff();
  const Eigen::Vector3d hi = surface.vertices.rowwise().maxCoeff();
  const Eigen::Vector3d extent = hi - lo;
  Eigen::Vector3i cells;
  for (int axis = 0; axis < 3; ++axis) cells[axis] = std::max(1, static_cast<int>(std::ceil(extent[axis] / spacing)));
  if (static_cast<double>(cells[0]) * cells[1] * cells[2] > static_cast<double>(maxSamples))
    throw InvalidInputError("interior sampling: spacing " + std::to_string(spacing) + " gives more than " +
                            std::to_string(maxSamples) + " grid cells");
  // The cells tile the bounding box exactly (per-axis step = extent / cells <= spacing), so the samples
  // reach every face of the box symmetrically. Cell centres are shifted by different irrational fractions
  // per axis so that rays do not run through the edges of regular inputs (axis-aligned or diagonal),
  // where a hit would count twice or not at all.
  Eigen::Vector3d step;
  for (int axis = 0; axis < 3; ++axis) step[axis] = extent[axis] > 0.0 ? extent[axis] / cells[axis] : spacing;
  const Eigen::Vector3d shift =
      1e-3 * step.cwiseProduct(Eigen::Vector3d(std::sqrt(2.0) - 1.0, std::sqrt(3.0) - 1.5, 0.1 * M_PI));
  const Eigen::Vector3d origin = lo + 0.5 * step + shift;
  const int nx = cells[0], ny = cells[1], nz = cells[2];

  // Crossing heights of every column's +z ray with the surface.
  std::vector<std::vector<double>> crossings(static_cast<std::size_t>(nx) * ny);
  for (Eigen::Index t = 0; t < surface.numTriangles(); ++t) {
    const Eigen::Vector3d a = surface.vertices.col(surface.triangles(0, t));
    const Eigen::Vector3d b = surface.vertices.col(surface.triangles(1, t));
    const Eigen::Vector3d c = surface.vertices.col(surface.triangles(2, t));
    const double area = (b.x() - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (b.y() - a.y());
    if (area == 0.0) continue;  // parallel to the rays
    const int i0 = std::max(0, static_cast<int>(std::ceil((std::min({a.x(), b.x(), c.x()}) - origin.x()) / step.x())));
    const int i1 = std::min(nx - 1, static_cast<int>(std::floor((std::max({a.x(), b.x(), c.x()}) - origin.x()) / step.x())));
    const int j0 = std::max(0, static_cast<int>(std::ceil((std::min({a.y(), b.y(), c.y()}) - origin.y()) / step.y())));
    const int j1 = std::min(ny - 1, static_cast<int>(std::floor((std::max({a.y(), b.y(), c.y()}) - origin.y()) / step.y())));
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) {
        const double x = origin.x() + i * step.x(), y = origin.y() + j * step.y();
        // Barycentric coordinates of the column in the projected triangle.
        const double wa = ((b.x() - x) * (c.y() - y) - (c.x() - x) * (b.y() - y)) / area;
        const double wb = ((c.x() - x) * (a.y() - y) - (a.x() - x) * (c.y() - y)) / area;
        const double wc = 1.0 - wa - wb;
        if (wa < 0.0 || wb < 0.0 || wc < 0.0) continue;
        crossings[static_cast<std::size_t>(j) * nx + i].push_back(wa * a.z() + wb * b.z() + wc * c.z());
      }
  }

  std::vector<Eigen::Vector3d> inside;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      std::vector<double>& column = crossings[static_cast<std::size_t>(j) * nx + i];
      if (column.size() % 2 != 0)
        throw InvalidInputError("interior sampling: a ray crosses the surface an odd number of times "
                                "(surface not closed, or not watertight)");
      std::sort(column.begin(), column.end());
      std::size_t below = 0;
      for (int k = 0; k < nz; ++k) {
        const double z = origin.z() + k * step.z();
        while (below < column.size() && column[below] < z) ++below;
        if (below % 2 == 1) inside.emplace_back(origin.x() + i * step.x(), origin.y() + j * step.y(), z);
      }
    }
  if (inside.empty()) throw InvalidInputError("interior sampling: no grid cell centre lies inside the surface");
  Eigen::Matrix3Xd points(3, inside.size());
  for (std::size_t m = 0; m < inside.size(); ++m) points.col(m) = inside[m];
  return PointSampling(std::move(points), Eigen::VectorXd::Constant(inside.size(), step.prod()));
}

}  // namespace deformation_enrichment::descriptors
