#pragma once
// Moving-least-squares deformation gradient by weighted shape matching (paper 000 §4.3 after
// Müller et al. 2005): F = A_pq A_qq^-1 with q_m = x_m - x_bar, p_m = y_m - y_bar,
// A_pq = sum w_m p_m q_mᵀ, A_qq = sum w_m q_m q_mᵀ. F minimises sum w_m |F q_m - p_m|^2.
//
// Near a flat contact the samples are (nearly) coplanar and A_qq is singular in the normal direction.
// Like deformation transfer's fourth vertex (Sumner & Popović 2004), the fit is then completed with the
// rest normal n_x and the deformed normal n_y: F maps n_x to lambda n_y, where lambda is chosen by
// NormalStretch (default: sqrt of the in-plane area ratio, which is what the fourth vertex
// v4 = v1 + e1 x e2 / sqrt|e1 x e2| implies).
#include <Eigen/Core>

namespace deformation_enrichment::kinematics {

/// How far the completed F stretches the normal direction (a flat sample set cannot tell).
enum class NormalStretch {
  DeformationTransfer,  ///< lambda = sqrt(in-plane area ratio), as deformation transfer's fourth vertex
  Unit,                 ///< lambda = 1: the normal keeps its length
  VolumePreserving,     ///< lambda = 1 / (in-plane area ratio): det F = +-1 (incompressible tissue)
};

struct MlsOptions {
  /// The sample set counts as coplanar when the smallest eigenvalue of A_qq is below this fraction of
  /// the largest (i.e. the out-of-plane spread is below sqrt(tolerance) of the in-plane spread). Below
  /// it, fitting the normal column from the points would amplify noise by 1/tolerance, so the normal
  /// completion is used instead (and required).
  double coplanarTolerance = 1e-6;
  NormalStretch normalStretch = NormalStretch::DeformationTransfer;
};

struct MlsDeformationGradient {
  Eigen::Matrix3d F;           ///< deformation gradient, F = A_pq A_qq^-1 (completed if flat)
  Eigen::Vector3d xBar;        ///< weighted rest centroid x_bar = sum w_m x_m / sum w_m
  Eigen::Vector3d yBar;        ///< weighted deformed centroid y_bar = sum w_m y_m / sum w_m
  bool normalCompleted = false;  ///< true if the samples were coplanar and the normals completed F
};

/// Shape-matching F from rest points x (3 x M), deformed points y (3 x M) and weights w (M, >= 0).
/// Samples must span 3D (else throws InvalidInputError asking for normals).
/// Throws InvalidInputError for empty input, mismatched sizes, NaN/Inf, negative weights, all-zero
/// weights, or samples that are collinear / coincident.
MlsDeformationGradient mlsDeformationGradient(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& y,
                                              const Eigen::VectorXd& w, const MlsOptions& options = {});

/// As above, with the rest and deformed surface normals at the evaluation point (need not be unit
/// length, must be non-zero; consistently oriented, e.g. both outward). They are used only when the
/// samples are coplanar (see MlsOptions::coplanarTolerance); a 3D sample set is fitted as is.
MlsDeformationGradient mlsDeformationGradient(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& y,
                                              const Eigen::VectorXd& w, const Eigen::Vector3d& restNormal,
                                              const Eigen::Vector3d& deformedNormal,
                                              const MlsOptions& options = {});

}  // namespace deformation_enrichment::kinematics
