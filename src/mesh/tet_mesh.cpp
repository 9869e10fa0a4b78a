#include "deformation_enrichment/mesh/tet_mesh.hpp"

#include <Eigen/Dense>
#include <string>

#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::mesh {

double signedVolume(const TetMesh& mesh, Eigen::Index t) {
  const Eigen::Vector4i tet = mesh.tets.col(t);
  Eigen::Matrix3d edges;
  for (int k = 0; k < 3; ++k) edges.col(k) = mesh.vertices.col(tet[k + 1]) - mesh.vertices.col(tet[0]);
  return edges.determinant() / 6.0;
}

double totalVolume(const TetMesh& mesh) {
  double volume = 0.0;
  for (Eigen::Index t = 0; t < mesh.numTets(); ++t) volume += signedVolume(mesh, t);
  return volume;
}

void validate(const TetMesh& mesh, bool requireNonDegenerate) {
  if (mesh.numVertices() == 0) throw InvalidInputError("tet mesh has no vertices");
  if (mesh.numTets() == 0) throw InvalidInputError("tet mesh has no tetrahedra");
  for (Eigen::Index v = 0; v < mesh.numVertices(); ++v) {
    if (!mesh.vertices.col(v).allFinite())
      throw InvalidInputError("tet mesh vertex " + std::to_string(v) + " is not finite");
  }
  const Eigen::Index n = mesh.numVertices();
  for (Eigen::Index t = 0; t < mesh.numTets(); ++t) {
    for (int k = 0; k < 4; ++k) {
      const int index = mesh.tets(k, t);
      if (index < 0 || index >= n)
        throw InvalidInputError("tet " + std::to_string(t) + " references vertex " + std::to_string(index) +
                                " but the mesh has " + std::to_string(n));
    }
    if (requireNonDegenerate && !(signedVolume(mesh, t) > 0.0))
      throw InvalidInputError("tet " + std::to_string(t) + " has non-positive volume " +
                              std::to_string(signedVolume(mesh, t)));
  }
}

Eigen::VectorXd lumpedVertexVolumes(const TetMesh& mesh) {
  Eigen::VectorXd volumes = Eigen::VectorXd::Zero(mesh.numVertices());
  for (Eigen::Index t = 0; t < mesh.numTets(); ++t) {
    const double quarter = std::abs(signedVolume(mesh, t)) / 4.0;
    for (int k = 0; k < 4; ++k) volumes[mesh.tets(k, t)] += quarter;
  }
  return volumes;
}

}  // namespace deformation_enrichment::mesh
