#include "deformation_enrichment/elasticity/rotation_variant_svd.hpp"

#include <Eigen/LU>
#include <Eigen/SVD>

#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::elasticity {

RotationVariantSvd rotationVariantSvd(const Eigen::Matrix3d& F) {
  if (!F.allFinite()) {
    throw InvalidInputError("rotationVariantSvd: deformation gradient has a non-finite entry");
  }
  // Eigen's JacobiSVD returns sigma sorted descending, sigma >= 0, U and V orthogonal (possibly det -1).
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(F, Eigen::ComputeFullU | Eigen::ComputeFullV);
  RotationVariantSvd out{svd.matrixU(), svd.singularValues(), svd.matrixV()};
  // Move each reflection into the smallest singular value (paper 001 §2: rotation-variant SVD).
  if (out.U.determinant() < 0.0) {
    out.U.col(2) *= -1.0;
    out.sigma(2) *= -1.0;
  }
  if (out.V.determinant() < 0.0) {
    out.V.col(2) *= -1.0;
    out.sigma(2) *= -1.0;
  }
  return out;
}

}  // namespace deformation_enrichment::elasticity
