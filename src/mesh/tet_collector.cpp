#include "tet_collector.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::mesh::detail {

TetCollector::TetCollector(std::string source, std::string locationKind)
    : source_(std::move(source)), locationKind_(std::move(locationKind)) {}

void TetCollector::add(const std::array<long, 4>& corners, int region, long location) {
  corners_.push_back(corners);
  regions_.push_back(region);
  locations_.push_back(location);
}

void TetCollector::fail(long location, const std::string& message) const {
  // Lines the way compilers name them (file:line:), anything else spelled out.
  const std::string where = locationKind_ == "line" ? ":" + std::to_string(location) + ": "
                                                    : ": " + locationKind_ + " " + std::to_string(location) + ": ";
  throw IoError(source_ + where + message);
}

VolumeMeshFile TetCollector::finish(Eigen::Matrix3Xd vertices, std::vector<long> nodeIds) {
  VolumeMeshFile file;
  const Eigen::Index nodes = vertices.cols();
  for (Eigen::Index v = 0; v < nodes; ++v)
    if (!vertices.col(v).allFinite())
      throw IoError(source_ + ": node " + std::to_string(nodeIds[static_cast<size_t>(v)]) + " is not finite");
  if (corners_.empty())
    throw IoError(source_ + " has no tetrahedra" + (skipped_.empty() ? "" : " (only other cells)"));
  file.mesh.vertices = std::move(vertices);
  file.mesh.tets.resize(4, static_cast<Eigen::Index>(corners_.size()));
  file.region = Eigen::Map<const Eigen::VectorXi>(regions_.data(), static_cast<Eigen::Index>(regions_.size()));
  std::vector<bool> used(static_cast<size_t>(nodes), false);
  for (size_t t = 0; t < corners_.size(); ++t) {
    const Eigen::Index tet = static_cast<Eigen::Index>(t);
    for (int k = 0; k < 4; ++k) {
      const long corner = corners_[t][static_cast<size_t>(k)];
      if (corner < 0 || corner >= nodes)
        fail(locations_[t], "node index " + std::to_string(corner) + " out of range [0, " + std::to_string(nodes) + ")");
      for (int j = 0; j < k; ++j)
        if (file.mesh.tets(j, tet) == corner) fail(locations_[t], "repeated node index " + std::to_string(corner));
      file.mesh.tets(k, tet) = static_cast<int>(corner);
      used[static_cast<size_t>(corner)] = true;
    }
    const double volume = signedVolume(file.mesh, tet);
    if (volume == 0.0 || !std::isfinite(volume)) fail(locations_[t], "tetrahedron has zero volume");
    if (volume < 0.0) {
      std::swap(file.mesh.tets(2, tet), file.mesh.tets(3, tet));
      ++file.report.reorientedTets;
    }
  }
  file.report.skippedCells = std::move(skipped_);
  file.report.unusedNodes = std::count(used.begin(), used.end(), false);
  file.nodeIds = std::move(nodeIds);
  return file;
}

}  // namespace deformation_enrichment::mesh::detail
