#include "deformation_enrichment/shape_space/shape_sequence.hpp"

#include <string>

#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::shape_space {

Eigen::VectorXd flatten(const Eigen::Matrix3Xd& vertices) {
  return Eigen::Map<const Eigen::VectorXd>(vertices.data(), vertices.size());
}

Eigen::Matrix3Xd unflatten(const Eigen::VectorXd& positions) {
  if (positions.size() % 3 != 0)
    throw InvalidInputError("position vector length " + std::to_string(positions.size()) + " is not a multiple of 3");
  return Eigen::Map<const Eigen::Matrix3Xd>(positions.data(), 3, positions.size() / 3);
}

ShapeSequence makeSequence(const std::vector<mesh::TriangleMesh>& meshes, int minShapes) {
  if (int(meshes.size()) < minShapes)
    throw InvalidInputError("a shape sequence needs at least " + std::to_string(minShapes) + " shapes, got " +
                            std::to_string(meshes.size()));
  ShapeSequence sequence;
  sequence.triangles = meshes.front().triangles;
  for (size_t i = 0; i < meshes.size(); ++i) {
    const mesh::TriangleMesh& m = meshes[i];
    if (m.numVertices() != meshes.front().numVertices())
      throw InvalidInputError("shape " + std::to_string(i) + " has " + std::to_string(m.numVertices()) +
                              " vertices, shape 0 has " + std::to_string(meshes.front().numVertices()));
    if (m.triangles.cols() != sequence.triangles.cols() || m.triangles != sequence.triangles)
      throw InvalidInputError("shape " + std::to_string(i) + " has a different triangle list than shape 0");
    sequence.shapes.push_back(flatten(m.vertices));
  }
  validateSequence(sequence, minShapes);
  return sequence;
}

void validateSequence(const ShapeSequence& sequence, int minShapes) {
  if (int(sequence.shapes.size()) < minShapes)
    throw InvalidInputError("a shape sequence needs at least " + std::to_string(minShapes) + " shapes, got " +
                            std::to_string(sequence.shapes.size()));
  const Eigen::Index n = sequence.shapes.front().size();
  for (size_t i = 0; i < sequence.shapes.size(); ++i) {
    if (sequence.shapes[i].size() != n)
      throw InvalidInputError("shape " + std::to_string(i) + " has " + std::to_string(sequence.shapes[i].size()) +
                              " coordinates, shape 0 has " + std::to_string(n));
    try {
      mesh::validate(shapeMesh(sequence, Eigen::Index(i)), true);
    } catch (const InvalidInputError& e) {
      throw InvalidInputError("shape " + std::to_string(i) + ": " + e.what());
    }
  }
}

mesh::TriangleMesh shapeMesh(const ShapeSequence& sequence, Eigen::Index i) {
  if (i < 0 || i >= sequence.numShapes())
    throw InvalidInputError("shape index " + std::to_string(i) + " out of range");
  return mesh::TriangleMesh{unflatten(sequence.shapes[size_t(i)]), sequence.triangles};
}

}  // namespace deformation_enrichment::shape_space
