#pragma once
// Vertex one-rings of a triangle mesh in compressed rows (vertices joined by a triangle edge), built once so
// that walks over the surface (e.g. the part of a stamp's ball reachable through the surface) cost the
// size of what they visit, not of the mesh.
#include <Eigen/Core>
#include <vector>

namespace deformation_enrichment::mesh {

struct VertexAdjacency {
  std::vector<int> start;       ///< size V + 1; the neighbours of v are neighbours[start[v], start[v + 1])
  std::vector<int> neighbours;  ///< ascending per vertex, each once, never the vertex itself

  Eigen::Index numVertices() const { return start.empty() ? 0 : static_cast<Eigen::Index>(start.size()) - 1; }
  const int* begin(int v) const { return neighbours.data() + start[static_cast<std::size_t>(v)]; }
  const int* end(int v) const { return neighbours.data() + start[static_cast<std::size_t>(v) + 1]; }
};

/// One-rings over the triangles' edges; vertices no triangle uses have empty rings. Throws
/// InvalidInputError for indices outside [0, numVertices) or a negative numVertices.
VertexAdjacency vertexAdjacency(const Eigen::Matrix3Xi& triangles, Eigen::Index numVertices);

}  // namespace deformation_enrichment::mesh
