#pragma once
// Per-triangle 2D deformation gradient ([Yan19 eq. 2], after [Rohmer10]): F = [u1 u2][ū1 ū2]^-1
// with ū_i the rest edges and u_i the deformed edges, each expressed in its own triangle's orthonormal
// 2D frame (not by dropping a 3D coordinate, which the seed's log does and which is wrong for every
// triangle not parallel to the xy-plane). Stretch U = sqrt(C), C = FᵀF ([Yan19 eqs. 15-20]), from the
// eigen decomposition of C. Used for strain colouring.
#include <Eigen/Core>

#include "deformation_enrichment/mesh/triangle_mesh.hpp"

namespace deformation_enrichment::kinematics {

/// Orthonormal 2D frame in a triangle's plane: e1 along edge v0->v1, e2 in the plane towards v2.
/// Local coordinates of a vector a in the plane: axesᵀ a.
struct TriangleFrame {
  Eigen::Matrix<double, 3, 2> axes;  ///< columns e1, e2
  Eigen::Vector3d normal;            ///< e1 x e2 (unit, right-handed with the vertex order)
};

struct TriangleStrain {
  Eigen::Matrix2d F;  ///< 2D deformation gradient: deformed-frame coordinates of the image of rest-frame ones
  Eigen::Matrix2d U;  ///< right stretch tensor U = sqrt(FᵀF), in rest-frame coordinates (symmetric PSD)
  Eigen::Vector2d principalStretches;   ///< eigenvalues of U, descending
  Eigen::Matrix2d principalDirections;  ///< matching unit eigenvectors (columns), rest-frame coordinates
  TriangleFrame restFrame;
  TriangleFrame deformedFrame;  ///< if the deformed triangle collapsed: a deterministic fallback frame
};

/// Orthonormal frame of a triangle. Throws InvalidInputError if the triangle is degenerate (area below
/// 1e-12 times its longest squared edge) or has non-finite vertices.
TriangleFrame triangleFrame(const Eigen::Vector3d& v0, const Eigen::Vector3d& v1, const Eigen::Vector3d& v2);

/// Strain of one triangle from its rest vertices X0, X1, X2 and deformed vertices x0, x1, x2.
/// The rest triangle must be non-degenerate (else InvalidInputError); the deformed one may collapse
/// (stretches 0 are then reported, never NaN).
TriangleStrain triangleDeformationGradient(const Eigen::Vector3d& X0, const Eigen::Vector3d& X1,
                                           const Eigen::Vector3d& X2, const Eigen::Vector3d& x0,
                                           const Eigen::Vector3d& x1, const Eigen::Vector3d& x2);

/// Principal stretches (2 x T, row 0 the larger) of every triangle of rest, deformed to the vertex
/// positions of deformed (same triangles). Throws InvalidInputError if the meshes do not match (vertex
/// or triangle counts, indices), if rest is invalid or has a degenerate triangle, or if deformed has
/// non-finite positions.
Eigen::Matrix2Xd principalStretches(const mesh::TriangleMesh& rest, const mesh::TriangleMesh& deformed);

}  // namespace deformation_enrichment::kinematics
