#include "deformation_enrichment/descriptors/sample_grid.hpp"

#include <algorithm>
#include <cmath>

#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::descriptors {

void SampleGrid::centresWithin(int axis, double lo, double hi, int& first, int& last) const {
  first = std::max(0, static_cast<int>(std::ceil((lo - origin[axis]) / step[axis])));
  last = std::min(cells[axis] - 1, static_cast<int>(std::floor((hi - origin[axis]) / step[axis])));
}

SampleGrid SampleGrid::grown(int extra) const {
  SampleGrid g = *this;
  g.origin -= extra * step;
  g.cells += Eigen::Vector3i::Constant(2 * extra);
  return g;
}

SampleGrid sampleGrid(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, double spacing, long maxCells,
                      const std::string& what) {
  if (!(spacing > 0.0) || !std::isfinite(spacing))
    throw InvalidInputError(what + ": spacing must be positive, got " + std::to_string(spacing));
  if (!lo.allFinite() || !hi.allFinite()) throw InvalidInputError(what + ": the box to sample is not finite");
  const Eigen::Vector3d extent = hi - lo;
  SampleGrid grid;
  double count = 1.0;
  for (int axis = 0; axis < 3; ++axis) {
    const double cells = std::max(1.0, std::ceil(extent[axis] / spacing));
    count *= cells;
    if (count > static_cast<double>(maxCells))
      throw InvalidInputError(what + ": spacing " + std::to_string(spacing) + " m gives more than " +
                              std::to_string(maxCells) + " grid cells");
    grid.cells[axis] = static_cast<int>(cells);
    grid.step[axis] = extent[axis] > 0.0 ? extent[axis] / cells : spacing;
  }
  const Eigen::Vector3d shift =
      1e-3 * grid.step.cwiseProduct(Eigen::Vector3d(std::sqrt(2.0) - 1.0, std::sqrt(3.0) - 1.5, 0.1 * M_PI));
  grid.origin = lo + 0.5 * grid.step + shift;
  return grid;
}

}  // namespace deformation_enrichment::descriptors
