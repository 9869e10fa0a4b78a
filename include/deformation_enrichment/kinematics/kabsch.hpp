#pragma once
// Kabsch algorithm: the proper rotation R and translation t minimising sum w_m |R x_m + t - y_m|^2
// between weighted point sets ([Yan19]: the 3D rotation between rest and deformed triangle or MLS
// neighbourhood). Reflection fix: if the best orthogonal map is a reflection, the axis of the smallest
// singular value of the cross-covariance is flipped, so det R = +1 always.
#include <Eigen/Core>

namespace deformation_enrichment::kinematics {

struct RigidTransform {
  Eigen::Matrix3d R;  ///< proper rotation
  Eigen::Vector3d t;  ///< translation: y ≈ R x + t, t = y_bar - R x_bar
  /// Whether R is unique: false when the weighted cross-covariance has rank <= 1 (all samples on one
  /// line through the centroids, or coincident); R is then one of the minimisers.
  bool unique = true;
};

/// Kabsch with weights w (M, >= 0, not all zero). x and y are 3 x M.
/// Throws InvalidInputError for empty input, mismatched sizes, NaN/Inf, negative or all-zero weights.
RigidTransform kabsch(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& y, const Eigen::VectorXd& w);

/// Kabsch with equal weights.
RigidTransform kabsch(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& y);

}  // namespace deformation_enrichment::kinematics
