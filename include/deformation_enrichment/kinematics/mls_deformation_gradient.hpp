#pragma once
// Moving-least-squares deformation gradient by weighted shape matching ([Seiler14 §4.3] after
// Müller et al. 2005): F = A_pq A_qq^-1 with q_m = x_m - x_bar, p_m = y_m - y_bar,
// A_pq = sum w_m p_m q_mᵀ, A_qq = sum w_m q_m q_mᵀ. F minimises sum w_m |F q_m - p_m|^2.
//
// Two kinds of samples:
// - volume samples (tet mesh vertices): the plain fit above; they must span 3D.
// - surface samples with the rest and deformed surface normals n_x, n_y at the evaluation point. Near a
//   flat contact these are coplanar and A_qq is singular; and on a gently curved surface the normal
//   column of the plain fit comes from the tiny curvature offsets, which correlate with the (quadratic)
//   indentation profile and give wild, even inverted, F. So, like deformation transfer's fourth vertex
//   (Sumner & Popović 2004), the normal direction comes from the normals: the tangential columns are
//   fitted from the rest offsets projected on the rest tangent plane and the deformed offsets projected
//   on the deformed tangent plane, and F maps n_x to lambda n_y, lambda chosen by NormalStretch
//   (default: sqrt of the tangential area ratio, as the fourth vertex v4 = v1 + e1 x e2 / sqrt|e1 x e2|).
//   This F is exact for rigid motions of any patch and for affine maps A of a flat patch when the
//   normals are consistent (n_y ∝ A^-T n_x, A n_x = lambda n_y).
#include <Eigen/Core>

namespace deformation_enrichment::kinematics {

/// How far the completed F stretches the normal direction (a flat sample set cannot tell).
enum class NormalStretch {
  DeformationTransfer,  ///< lambda = sqrt(in-plane area ratio), as deformation transfer's fourth vertex
  Unit,                 ///< lambda = 1: the normal keeps its length
  VolumePreserving,     ///< lambda = 1 / (in-plane area ratio): det F = +-1 (incompressible tissue)
};

struct MlsOptions {
  /// Volume samples count as coplanar (error: pass normals) when the smallest eigenvalue of A_qq is below
  /// this fraction of the largest, i.e. the out-of-plane spread is below sqrt(tolerance) of the largest
  /// spread; fitting F there would amplify noise by 1/tolerance. The same test on the middle eigenvalue
  /// (on the 2x2 tangential A_qq for surface samples) rejects collinear samples.
  double coplanarTolerance = 1e-6;
  NormalStretch normalStretch = NormalStretch::DeformationTransfer;
};

struct MlsDeformationGradient {
  Eigen::Matrix3d F;           ///< deformation gradient (volume: A_pq A_qq^-1; surface: G + lambda n_y n_xᵀ)
  Eigen::Vector3d xBar;        ///< weighted rest centroid x_bar = sum w_m x_m / sum w_m
  Eigen::Vector3d yBar;        ///< weighted deformed centroid y_bar = sum w_m y_m / sum w_m
  bool normalCompleted = false;  ///< true if the normal column came from the surface normals (surface samples)
};

/// Shape-matching F from rest points x (3 x M), deformed points y (3 x M) and weights w (M, >= 0).
/// Samples must span 3D (else throws InvalidInputError asking for normals).
/// Throws InvalidInputError for empty input, mismatched sizes, NaN/Inf, negative weights, all-zero
/// weights, or samples that are collinear / coincident.
MlsDeformationGradient mlsDeformationGradient(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& y,
                                              const Eigen::VectorXd& w, const MlsOptions& options = {});

/// Surface samples with the rest and deformed surface normals at the evaluation point (need not be unit
/// length, must be non-zero; consistently oriented, e.g. both outward): tangential fit plus normal
/// completion, see the top of this file. Works for flat and curved patches alike. Throws
/// InvalidInputError as above, for zero or non-finite normals, and when the samples projected on the
/// rest tangent plane are collinear (e.g. a rest normal lying in the plane of a flat patch).
MlsDeformationGradient mlsDeformationGradient(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& y,
                                              const Eigen::VectorXd& w, const Eigen::Vector3d& restNormal,
                                              const Eigen::Vector3d& deformedNormal,
                                              const MlsOptions& options = {});

}  // namespace deformation_enrichment::kinematics
