#pragma once
// Shared last step of the volume-mesh readers (private to src/mesh): the tets a reader found, with where
// in the file each came from, checked and oriented once all node positions are known.
#include <array>
#include <map>
#include <string>
#include <vector>

#include "deformation_enrichment/mesh/volume_mesh_io.hpp"

namespace deformation_enrichment::mesh::detail {

class TetCollector {
public:
  /// `source` names the file, `locationKind` what a location is ("line", "element", "cell").
  TetCollector(std::string source, std::string locationKind);

  /// A tet with 0-based corners (checked in finish), its region and where it was read.
  void add(const std::array<long, 4>& corners, int region, long location);
  /// `count` cells that are not tets.
  void skip(const std::string& cellType, long count = 1) { skipped_[cellType] += count; }
  long size() const { return static_cast<long>(regions_.size()); }

  /// Throws IoError naming the tet's location for a corner outside [0, vertices.cols()), a repeated
  /// corner or a zero-volume tet, and naming the node for a non-finite position; reorders inverted tets.
  VolumeMeshFile finish(Eigen::Matrix3Xd vertices, std::vector<long> nodeIds);

  [[noreturn]] void fail(long location, const std::string& message) const;

private:
  std::string source_, locationKind_;
  std::vector<std::array<long, 4>> corners_;
  std::vector<int> regions_;
  std::vector<long> locations_;
  std::map<std::string, long> skipped_;
};

}  // namespace deformation_enrichment::mesh::detail
