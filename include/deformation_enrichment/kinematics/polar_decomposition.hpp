#pragma once
// Polar decomposition F = R S of a 3x3 deformation gradient ([Seiler14 §4.3]: "F = grad u + I = R S"),
// with R a proper rotation (det R = +1) and S symmetric. Computed from Eigen's SVD so it is defined for
// every finite F: near-singular, rank-deficient and inverted (det F < 0) ones included.
#include <Eigen/Core>

namespace deformation_enrichment::kinematics {

/// F = R S. For det F >= 0, S is positive semi-definite (the classical right stretch tensor). For an
/// inverted F (det F < 0) a proper rotation cannot absorb the reflection, so S carries it: S has exactly
/// one negative eigenvalue, the one belonging to the smallest singular value ("rotation-variant" SVD).
struct PolarDecomposition {
  Eigen::Matrix3d R;  ///< proper rotation, RᵀR = I, det R = +1
  Eigen::Matrix3d S;  ///< symmetric, F = R S
};

/// Polar decomposition of F via the SVD F = U Σ Vᵀ: R = U D Vᵀ, S = V D Σ Vᵀ, D = diag(1, 1, det(U Vᵀ)).
/// R is unique when F has rank >= 2; for rank <= 1 it is one of the minimisers of |F - R|_F.
/// Throws InvalidInputError if F has a NaN or infinite entry.
PolarDecomposition polarDecomposition(const Eigen::Matrix3d& F);

}  // namespace deformation_enrichment::kinematics
