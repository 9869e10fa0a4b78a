#include "deformation_enrichment/mesh/vertex_adjacency.hpp"

#include <algorithm>
#include <string>

#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::mesh {

VertexAdjacency vertexAdjacency(const Eigen::Matrix3Xi& triangles, Eigen::Index numVertices) {
  if (numVertices < 0) throw InvalidInputError("vertex adjacency: negative vertex count");
  for (Eigen::Index t = 0; t < triangles.cols(); ++t)
    for (int k = 0; k < 3; ++k)
      if (triangles(k, t) < 0 || triangles(k, t) >= numVertices)
        throw InvalidInputError("vertex adjacency: triangle " + std::to_string(t) + " has vertex index " +
                                std::to_string(triangles(k, t)) + " outside [0, " + std::to_string(numVertices) + ")");
  // Two passes (count, fill) into one array: no per-vertex allocations on meshes of 10^5 vertices.
  const auto n = static_cast<std::size_t>(numVertices);
  std::vector<int> count(n + 1, 0);
  for (Eigen::Index t = 0; t < triangles.cols(); ++t)
    for (int k = 0; k < 3; ++k) count[static_cast<std::size_t>(triangles(k, t)) + 1] += 2;
  for (std::size_t v = 0; v < n; ++v) count[v + 1] += count[v];
  std::vector<int> slots(static_cast<std::size_t>(count[n]));
  std::vector<int> fill(count.begin(), count.end() - 1);
  for (Eigen::Index t = 0; t < triangles.cols(); ++t)
    for (int k = 0; k < 3; ++k) {
      const auto v = static_cast<std::size_t>(triangles(k, t));
      slots[static_cast<std::size_t>(fill[v]++)] = triangles((k + 1) % 3, t);
      slots[static_cast<std::size_t>(fill[v]++)] = triangles((k + 2) % 3, t);
    }
  VertexAdjacency adjacency;
  adjacency.start.assign(1, 0);
  adjacency.start.reserve(n + 1);
  adjacency.neighbours.reserve(slots.size() / 2);  // a closed manifold shares every edge by two triangles
  for (std::size_t v = 0; v < n; ++v) {
    const auto first = slots.begin() + count[v], last = slots.begin() + count[v + 1];
    std::sort(first, last);
    for (auto it = first; it != last; ++it)
      if (*it != static_cast<int>(v) && (it == first || *it != *(it - 1))) adjacency.neighbours.push_back(*it);
    adjacency.start.push_back(static_cast<int>(adjacency.neighbours.size()));
  }
  return adjacency;
}

}  // namespace deformation_enrichment::mesh
