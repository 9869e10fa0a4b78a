#pragma once
// The regular grid whose cell centres sample a volume for the site density ([Seiler14 eq. 8] as a midpoint
// rule): cells tile a box exactly (per-axis step = extent / cells <= spacing), so samples reach every face
// of the box symmetrically, and centres are shifted by different irrational fractions of a cell per axis so
// that rays and nearest-point queries do not run exactly through the edges of regular inputs.
#include <Eigen/Core>
#include <string>

namespace deformation_enrichment::descriptors {

struct SampleGrid {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();  ///< centre of cell (0, 0, 0)
  Eigen::Vector3d step = Eigen::Vector3d::Ones();
  Eigen::Vector3i cells = Eigen::Vector3i::Ones();

  Eigen::Vector3d centre(int i, int j, int k) const {
    return origin + Eigen::Vector3d(i * step.x(), j * step.y(), k * step.z());
  }
  double cellVolume() const { return step.prod(); }
  /// The same grid with `cells` more cells on every side (the same centres where both have cells).
  SampleGrid grown(int cells) const;
  /// Index range [first, last] of the cells whose centres lie in [lo, hi] along `axis` (empty: first > last).
  void centresWithin(int axis, double lo, double hi, int& first, int& last) const;
};

/// The grid over the box [lo, hi]. Throws InvalidInputError naming `what` for a non-positive or non-finite
/// spacing, a non-finite box, or more than `maxCells` cells.
SampleGrid sampleGrid(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, double spacing, long maxCells,
                      const std::string& what);

}  // namespace deformation_enrichment::descriptors
