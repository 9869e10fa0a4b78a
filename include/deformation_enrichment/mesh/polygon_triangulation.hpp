#pragma once
// Fan triangulation of polygon lists as file formats and messages store them.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::mesh {

/// Splits every polygon (a range of integer vertex indices) with at least three corners into a triangle
/// fan; points and lines are skipped. Throws InvalidInputError for an index outside [0, numVertices).
template <class PolygonRange, class IndexOf>
Eigen::Matrix3Xi fanTriangulate(const PolygonRange& polygons, Eigen::Index numVertices, IndexOf cornersOf) {
  std::vector<Eigen::Vector3i> triangles;
  size_t polygonIndex = 0;
  for (const auto& polygon : polygons) {
    const auto& corners = cornersOf(polygon);
    for (const auto index : corners) {
      if (static_cast<long long>(index) < 0 || static_cast<long long>(index) >= numVertices)
        throw InvalidInputError("polygon " + std::to_string(polygonIndex) + " references vertex " +
                                std::to_string(static_cast<long long>(index)) + " of " + std::to_string(numVertices));
    }
    for (size_t k = 1; k + 1 < corners.size(); ++k)
      triangles.emplace_back(static_cast<int>(corners[0]), static_cast<int>(corners[k]), static_cast<int>(corners[k + 1]));
    ++polygonIndex;
  }
  Eigen::Matrix3Xi result(3, static_cast<Eigen::Index>(triangles.size()));
  for (size_t t = 0; t < triangles.size(); ++t) result.col(static_cast<Eigen::Index>(t)) = triangles[t];
  return result;
}

}  // namespace deformation_enrichment::mesh
