#pragma once
// A segmented 3D image (one 8-bit label per voxel, 0 = outside), read by CGAL's ImageIO: INRIMAGE
// (.inr, .inr.gz, as CGAL's liver [CGAL-data]), Analyze (.hdr/.img) and the other formats ImageIO reads.
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

namespace deformation_enrichment::mesh {

struct LabelImage {
  Eigen::Vector3i size = Eigen::Vector3i::Zero();     ///< voxels along x, y, z
  Eigen::Vector3d spacing = Eigen::Vector3d::Zero();  ///< voxel size in metres
  std::vector<std::uint8_t> labels;                   ///< x fastest, then y, then z

  std::uint8_t at(int x, int y, int z) const {
    return labels[static_cast<size_t>(x) + static_cast<size_t>(size.x()) * (static_cast<size_t>(y) + static_cast<size_t>(size.y()) * static_cast<size_t>(z))];
  }
};

/// Reads an 8-bit image; its voxel size is taken to be in millimetres (as medical images store it) and
/// converted to metres. Throws IoError naming the file when it cannot be read, is not 8-bit unsigned,
/// or has a non-positive voxel size.
LabelImage readLabelImage(const std::string& path);

}  // namespace deformation_enrichment::mesh
