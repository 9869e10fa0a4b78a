#include "deformation_enrichment/descriptors/deformation_descriptor.hpp"

#include <string>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/hermite/multi_index.hpp"
#include "deformation_enrichment/kinematics/polar_decomposition.hpp"

namespace deformation_enrichment::descriptors {

Eigen::Matrix3Xd rigidFreeDisplacement(const Eigen::Matrix3Xd& rest, const Eigen::Matrix3Xd& deformed,
                                       const Eigen::Matrix3d& R, const Eigen::Vector3d& t) {
  if (rest.cols() != deformed.cols())
    throw InvalidInputError("rigidFreeDisplacement: rest and deformed point counts differ");
  // eq. (10): u_bar(x) = R^T (x + u - t) - x, a fixed-size product per point
  const Eigen::Matrix3d Rt = R.transpose();
  Eigen::Matrix3Xd uBar(3, rest.cols());
  for (Eigen::Index k = 0; k < rest.cols(); ++k) uBar.col(k).noalias() = Rt * (deformed.col(k) - t) - rest.col(k);
  return uBar;
}

DeformationDescriptor deformationDescriptor(const Window& window, const Eigen::Matrix3Xd& restPoints,
                                            const Eigen::Matrix3Xd& deformedPoints, int order,
                                            const Eigen::Vector3d* restNormal,
                                            const Eigen::Vector3d* deformedNormal,
                                            const kinematics::MlsOptions& mls) {
  if (restPoints.cols() != deformedPoints.cols())
    throw InvalidInputError("deformation descriptor: " + std::to_string(deformedPoints.cols()) +
                            " deformed positions for " + std::to_string(restPoints.cols()) + " rest points");
  for (const int index : window.indices)
    if (index < 0 || index >= restPoints.cols())
      throw InvalidInputError("deformation descriptor: window index out of range of the point set");
  return windowDeformationDescriptor(window, restPoints(Eigen::all, window.indices), deformedPoints(Eigen::all, window.indices),
                                     order, restNormal, deformedNormal, mls);
}

DeformationDescriptor windowDeformationDescriptor(const Window& window, const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& y,
                                                  int order, const Eigen::Vector3d* restNormal,
                                                  const Eigen::Vector3d* deformedNormal, const kinematics::MlsOptions& mls) {
  if (order < 1 || order > hermite::kMaxHermiteOrder)
    throw InvalidInputError("deformation descriptor order " + std::to_string(order) + " outside [1, " +
                            std::to_string(hermite::kMaxHermiteOrder) + "]");
  if (window.empty())
    throw InvalidInputError("deformation descriptor: no sample within the cut-off radius of the contact "
                            "(contact far from the mesh?)");
  if (x.cols() != window.r.cols() || y.cols() != window.r.cols())
    throw InvalidInputError("deformation descriptor: " + std::to_string(x.cols()) + " rest and " + std::to_string(y.cols()) +
                            " deformed samples for a window of " + std::to_string(window.r.cols()));
  if (!y.allFinite()) throw InvalidInputError("deformation descriptor: deformed positions contain NaN or Inf");

  const kinematics::MlsDeformationGradient fit =
      (restNormal != nullptr && deformedNormal != nullptr)
          ? kinematics::mlsDeformationGradient(x, y, window.weight, *restNormal, *deformedNormal, mls)
          : kinematics::mlsDeformationGradient(x, y, window.weight, mls);
  const kinematics::PolarDecomposition polar = kinematics::polarDecomposition(fit.F);

  DeformationDescriptor result;
  result.F = fit.F;
  result.R = polar.R;
  result.S = polar.S;
  result.t = fit.yBar - polar.R * fit.xBar;  // t = y_bar - R x_bar
  result.xBar = fit.xBar;
  result.yBar = fit.yBar;
  result.normalCompleted = fit.normalCompleted;
  const Eigen::Matrix3Xd uBar = rigidFreeDisplacement(x, y, result.R, result.t);
  result.mu = fieldMoments(window, uBar, 1, order);  // eq. (11)
  return result;
}

}  // namespace deformation_enrichment::descriptors
