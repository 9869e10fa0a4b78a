#include "deformation_enrichment/descriptors/interior_sampling.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "deformation_enrichment/descriptors/sample_grid.hpp"
#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::descriptors {

PointSampling sampleClosedSurfaceInterior(const mesh::TriangleMesh& surface, double spacing, long maxSamples) {
  mesh::validate(surface, false);
  const SampleGrid grid = sampleGrid(surface.vertices.rowwise().minCoeff(), surface.vertices.rowwise().maxCoeff(), spacing,
                                     maxSamples, "interior sampling");
  const Eigen::Vector3d& origin = grid.origin;
  const Eigen::Vector3d& step = grid.step;
  const int nx = grid.cells[0], ny = grid.cells[1], nz = grid.cells[2];

  // Crossing heights of every column's +z ray with the surface.
  std::vector<std::vector<double>> crossings(static_cast<std::size_t>(nx) * ny);
  for (Eigen::Index t = 0; t < surface.numTriangles(); ++t) {
    const Eigen::Vector3d a = surface.vertices.col(surface.triangles(0, t));
    const Eigen::Vector3d b = surface.vertices.col(surface.triangles(1, t));
    const Eigen::Vector3d c = surface.vertices.col(surface.triangles(2, t));
    const double area = (b.x() - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (b.y() - a.y());
    if (area == 0.0) continue;  // parallel to the rays
    int i0, i1, j0, j1;
    grid.centresWithin(0, std::min({a.x(), b.x(), c.x()}), std::max({a.x(), b.x(), c.x()}), i0, i1);
    grid.centresWithin(1, std::min({a.y(), b.y(), c.y()}), std::max({a.y(), b.y(), c.y()}), j0, j1);
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
  return PointSampling(std::move(points), Eigen::VectorXd::Constant(inside.size(), grid.cellVolume()));
}

}  // namespace deformation_enrichment::descriptors
