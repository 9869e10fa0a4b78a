#pragma once
// An open surface made from a closed one for the tests: its top face alone (the triangles whose corners all
// lie at the top height), every vertex kept so states of the closed surface fit it.
#include <vector>

#include "deformation_enrichment/mesh/triangle_mesh.hpp"

namespace de_test {

inline deformation_enrichment::mesh::TriangleMesh topFace(const deformation_enrichment::mesh::TriangleMesh& closed, double top) {
  deformation_enrichment::mesh::TriangleMesh open = closed;
  std::vector<Eigen::Index> kept;
  for (Eigen::Index t = 0; t < closed.numTriangles(); ++t) {
    bool onTop = true;
    for (int k = 0; k < 3; ++k) onTop = onTop && closed.vertices(2, closed.triangles(k, t)) > top - 1e-4;
    if (onTop) kept.push_back(t);
  }
  open.triangles.resize(3, static_cast<Eigen::Index>(kept.size()));
  for (std::size_t i = 0; i < kept.size(); ++i) open.triangles.col(static_cast<Eigen::Index>(i)) = closed.triangles.col(kept[i]);
  return open;
}

}  // namespace de_test
