#pragma once
// Rotation-variant SVD of a 3x3 deformation gradient ([Smith18 §3], [Masanti19 eq. 2.3]):
// F = U diag(sigma) V^T with U, V proper rotations (det = +1). A reflection in F is moved into the
// smallest singular value, which is then negative, so sign(sigma_0 sigma_1 sigma_2) = sign(det F).
// The SNH eigensystem (twist/flip/scaling modes) is only valid in this form.
#include <Eigen/Core>

namespace deformation_enrichment::elasticity {

struct RotationVariantSvd {
  Eigen::Matrix3d U;      ///< rotation, det(U) = +1
  Eigen::Vector3d sigma;  ///< sigma_0 >= sigma_1 >= |sigma_2|; sigma_2 < 0 iff det F < 0
  Eigen::Matrix3d V;      ///< rotation, det(V) = +1
};

/// Throws InvalidInputError if F has a non-finite entry. Well defined for F = 0 and rank-deficient F
/// (U, V are then some rotations completing the null space). Singular values are sorted by magnitude up to
/// rounding at (near-)ties.
RotationVariantSvd rotationVariantSvd(const Eigen::Matrix3d& F);

}  // namespace deformation_enrichment::elasticity
