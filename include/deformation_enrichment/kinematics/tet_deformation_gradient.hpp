#pragma once
// Per-tetrahedron deformation gradient F = Ds Dm^-1 (constant strain tet), with the rest edge matrix
// Dm = [X1-X0, X2-X0, X3-X0] and the deformed one Ds = [x1-x0, x2-x0, x3-x0].
#include <vector>

#include <Eigen/Core>
#include <Eigen/StdVector>

#include "deformation_enrichment/mesh/tet_mesh.hpp"

namespace deformation_enrichment::kinematics {

using Matrix34d = Eigen::Matrix<double, 3, 4>;
using Matrix3dList = std::vector<Eigen::Matrix3d, Eigen::aligned_allocator<Eigen::Matrix3d>>;

/// Dm^-1 of one tet (columns of rest: X0..X3). Throws InvalidInputError for non-finite vertices or a
/// degenerate tet (|volume| below 1e-12 times the cube of its longest edge). Either orientation is fine.
Eigen::Matrix3d restShapeInverse(const Matrix34d& rest);

/// F = Ds Dm^-1 of one tet (columns: vertices 0..3). Same errors as restShapeInverse, and for a
/// non-finite deformed vertex. Inverted deformed tets give det F < 0 (not an error).
Eigen::Matrix3d tetDeformationGradient(const Matrix34d& rest, const Matrix34d& deformed);

/// Dm^-1 for every tet of a mesh, computed once and reused for many deformed states.
/// Throws InvalidInputError naming the tet if the mesh is invalid or has a degenerate tet.
Matrix3dList restShapeInverses(const mesh::TetMesh& rest);

/// F = Ds Dm^-1 for every tet, with Dm^-1 from restShapeInverses(rest) and deformed vertex positions
/// (3 x V, same vertex order). Throws InvalidInputError on size mismatch or non-finite positions.
Matrix3dList tetDeformationGradients(const mesh::TetMesh& rest, const Matrix3dList& restInverses,
                                     const Eigen::Matrix3Xd& deformedVertices);

/// Convenience: both steps at once.
Matrix3dList tetDeformationGradients(const mesh::TetMesh& rest, const Eigen::Matrix3Xd& deformedVertices);

}  // namespace deformation_enrichment::kinematics
