#include "deformation_enrichment/kinematics/polar_decomposition.hpp"

#include <Eigen/LU>
#include <Eigen/SVD>

#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::kinematics {

PolarDecomposition polarDecomposition(const Eigen::Matrix3d& F) {
  if (!F.allFinite()) {
    throw InvalidInputError("polarDecomposition: deformation gradient F has a NaN or infinite entry");
  }
  // Jacobi SVD: accurate singular vectors for small matrices, also for repeated or zero singular values.
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(F, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::Matrix3d& U = svd.matrixU();
  const Eigen::Matrix3d& V = svd.matrixV();
  Eigen::Vector3d sigma = svd.singularValues();  // descending, >= 0

  // Reflection fix: if U Vᵀ is improper, flip the axis of the smallest singular value (least change).
  Eigen::Vector3d d(1.0, 1.0, 1.0);
  if ((U * V.transpose()).determinant() < 0.0) d[2] = -1.0;

  PolarDecomposition result;
  result.R = U * d.asDiagonal() * V.transpose();
  const Eigen::Matrix3d S = V * (d.cwiseProduct(sigma)).asDiagonal() * V.transpose();
  result.S = 0.5 * (S + S.transpose());  // symmetric by construction; remove round-off asymmetry
  return result;
}

}  // namespace deformation_enrichment::kinematics
