#pragma once
// Interpolating shapes for initialising geodesics ([Brandt16 §6], coarse-to-fine refinement): rigid part by
// Kabsch alignment and quaternion slerp, non-rigid remainder linearly. A rigidly moved copy is therefore
// joined by the rigid path itself (zero elastic energy), and plain linear blending's shrinkage is avoided.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

namespace deformation_enrichment::shape_space {

struct RigidTransform {
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
};

/// Least-squares rigid motion (Kabsch, reflection fixed) moving `from` onto `to` (flat 3V vectors).
/// Throws InvalidInputError for sizes that differ or are not multiples of 3, or non-finite input.
RigidTransform kabsch(const Eigen::VectorXd& from, const Eigen::VectorXd& to);

/// Applies a rigid motion to a flat 3V vector.
Eigen::VectorXd applyRigid(const RigidTransform& motion, const Eigen::VectorXd& positions);

/// `shape` with each piece (a list of vertex indices, e.g. a connected component) moved rigidly onto the same
/// vertices of `target` (Kabsch per piece): the elastic energies do not see such motions. Throws
/// InvalidInputError for sizes that differ or indices out of range.
Eigen::VectorXd alignPieces(const Eigen::VectorXd& shape, const Eigen::VectorXd& target,
                            const std::vector<std::vector<int>>& pieces);

/// Shape at parameter t in [0, 1] between a and b: a's and b's centroids and orientations are blended
/// (slerp), the shapes after alignment linearly. t = 0 gives a, t = 1 gives b exactly.
Eigen::VectorXd rigidAwareInterpolation(const Eigen::VectorXd& a, const Eigen::VectorXd& b, double t);

}  // namespace deformation_enrichment::shape_space
