#pragma once
// A deformation sequence in shape space: one shared triangle topology and one flat 3V position vector per
// shape ([x0 y0 z0 x1 y1 z1 ...], the layout of the deformation-energy interface).
#include <vector>

#include <Eigen/Core>

#include "deformation_enrichment/mesh/triangle_mesh.hpp"

namespace deformation_enrichment::shape_space {

struct ShapeSequence {
  Eigen::Matrix3Xi triangles;            ///< shared topology
  std::vector<Eigen::VectorXd> shapes;   ///< flat 3V positions, one per shape

  Eigen::Index numVertices() const { return shapes.empty() ? 0 : shapes.front().size() / 3; }
  Eigen::Index numShapes() const { return Eigen::Index(shapes.size()); }
};

/// Flat 3V vector of a mesh's positions.
Eigen::VectorXd flatten(const Eigen::Matrix3Xd& vertices);
/// Inverse of flatten.
Eigen::Matrix3Xd unflatten(const Eigen::VectorXd& positions);

/// Builds a sequence from meshes. Throws InvalidInputError naming the offending shape if there are fewer
/// than minShapes meshes, vertex counts or triangle lists differ, or any mesh fails mesh::validate
/// (NaN/Inf, bad indices, degenerate triangles).
ShapeSequence makeSequence(const std::vector<mesh::TriangleMesh>& meshes, int minShapes = 3);

/// Checks an existing sequence the same way (every shape finite, same size, non-degenerate triangles).
void validateSequence(const ShapeSequence& sequence, int minShapes = 3);

/// Mesh of shape i.
mesh::TriangleMesh shapeMesh(const ShapeSequence& sequence, Eigen::Index i);

}  // namespace deformation_enrichment::shape_space
