#pragma once
// Closed-form eigen-decomposition of a symmetric 3x3 matrix, for the SNH scaling-mode block of the PSD
// projection ([Smith18 §4.3]: "the 3x3 scaling block solved small"). The isolated eigenvalue
// comes from the trigonometric solution of the characteristic cubic, its eigenvector from a cross
// product, and the remaining pair from an exact 2x2 rotation, so (near-)repeated eigenvalues keep full
// accuracy. Faster than Eigen's SelfAdjointEigenSolver<Matrix3d>::compute (bench_snh_projection).
#include <Eigen/Core>

namespace deformation_enrichment::elasticity {

struct SymmetricEigen3 {
  Eigen::Vector3d values;   ///< ascending
  Eigen::Matrix3d vectors;  ///< orthonormal eigenvectors as columns, det = +1
};

/// A must be symmetric with finite entries (only its upper triangle is read). Residual
/// |A V - V diag(values)| is a small multiple of machine epsilon times |A|.
SymmetricEigen3 symmetricEigen3(const Eigen::Matrix3d& A);

/// The nearest positive semi-definite matrix to the symmetric A (its negative eigenvalues set to 0), in
/// the Frobenius norm. Where the two eigenvalues other than the isolated one share a sign, only the
/// isolated eigenpair is computed. Same requirements on A as symmetricEigen3.
Eigen::Matrix3d psdProjection3(const Eigen::Matrix3d& A);

}  // namespace deformation_enrichment::elasticity
