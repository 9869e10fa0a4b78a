#include "deformation_enrichment/shape_space/ghost_mesh.hpp"

#include <string>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/edge_collapse.hpp"

namespace deformation_enrichment::shape_space {

Eigen::VectorXd GhostMesh::restrict(const Eigen::VectorXd& fine) const {
  Eigen::VectorXd ghost(3 * numVertices());
  for (Eigen::Index g = 0; g < numVertices(); ++g) ghost.segment<3>(3 * g) = fine.segment<3>(3 * fineVertices[size_t(g)]);
  return ghost;
}

Eigen::MatrixXd GhostMesh::restrictRows(const Eigen::MatrixXd& fine) const {
  Eigen::MatrixXd ghost(3 * numVertices(), fine.cols());
  for (Eigen::Index g = 0; g < numVertices(); ++g)
    ghost.middleRows<3>(3 * g) = fine.middleRows<3>(3 * fineVertices[size_t(g)]);
  return ghost;
}

GhostMesh ghostMesh(const Eigen::Matrix3Xi& triangles, const Eigen::VectorXd& reference, const GhostMeshOptions& options) {
  if (reference.size() % 3 != 0) throw InvalidInputError("ghost mesh: reference shape size is not a multiple of 3");
  // The half-edge collapse lives in the mesh module (also used for coarse volumes); its messages get
  // this module's prefix.
  mesh::EdgeCollapse collapse;
  try {
    collapse = mesh::collapseEdges(triangles, Eigen::Map<const Eigen::Matrix3Xd>(reference.data(), 3, reference.size() / 3),
                                   {options.targetVertices, options.minTriangleQuality});
  } catch (const InvalidInputError& e) {
    throw InvalidInputError(std::string("ghost mesh: ") + e.what());
  }
  GhostMesh ghost;
  ghost.fineVertices = std::move(collapse.keptVertices);
  ghost.triangles = std::move(collapse.triangles);
  return ghost;
}

}  // namespace deformation_enrichment::shape_space
