#pragma once
// Deformation descriptor mu of [Seiler14 §4.3]: MLS deformation gradient F at p from the window's samples
// (weighted shape matching, kinematics/), polar F = R S, translation t = y_bar - R x_bar, rigid-free
// displacement u_bar(x) = R^T (x + u - t) - x (eq. 10), and the Hermite moments of u_bar's three components
// of orders 1..N (eq. 11; mu_0 vanishes because the weighted mean of u_bar is removed).
#include <Eigen/Core>

#include "deformation_enrichment/descriptors/moment_window.hpp"
#include "deformation_enrichment/hermite/moment_list.hpp"
#include "deformation_enrichment/kinematics/mls_deformation_gradient.hpp"

namespace deformation_enrichment::descriptors {

struct DeformationDescriptor {
  Eigen::Matrix3d F = Eigen::Matrix3d::Identity();  ///< MLS deformation gradient at p
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();  ///< rotation of the polar decomposition F = R S
  Eigen::Matrix3d S = Eigen::Matrix3d::Identity();  ///< stretch of the polar decomposition
  Eigen::Vector3d t = Eigen::Vector3d::Zero();      ///< t = y_bar - R x_bar
  Eigen::Vector3d xBar = Eigen::Vector3d::Zero();   ///< weighted rest centroid of the window
  Eigen::Vector3d yBar = Eigen::Vector3d::Zero();   ///< weighted deformed centroid of the window
  bool normalCompleted = false;  ///< the samples were coplanar and the normals completed F
  hermite::MomentList mu;        ///< orders 1..N, 3 channels, in the rest shape's (world) axes
};

/// Rest-free displacement u_bar_m = R^T (y_m - t) - x_m of eq. (10), y_m = x_m + u_m.
Eigen::Matrix3Xd rigidFreeDisplacement(const Eigen::Matrix3Xd& rest, const Eigen::Matrix3Xd& deformed,
                                       const Eigen::Matrix3d& R, const Eigen::Vector3d& t);

/// mu at the window's centre. `restPoints` / `deformedPoints` are the whole sampling's rest and deformed
/// positions (the window indexes them). The MLS fit uses the window's quadrature weights q_m omega_m, so
/// the fit is as mesh-independent as the moments. Volume samples (tet vertices): pass no normals, F is the
/// plain shape-matching fit. Surface-only samples (a coarse state holding surface vertices): pass the rest
/// and deformed surface normals at p; kinematics' surface mode fits the tangential columns and completes
/// the normal one from the normals (flat and curved patches alike). Throws InvalidInputError for an
/// empty window (contact far from the mesh), mismatched sizes, NaN positions, or order outside [1, 4].
DeformationDescriptor deformationDescriptor(const Window& window, const Eigen::Matrix3Xd& restPoints,
                                            const Eigen::Matrix3Xd& deformedPoints, int order,
                                            const Eigen::Vector3d* restNormal = nullptr,
                                            const Eigen::Vector3d* deformedNormal = nullptr,
                                            const kinematics::MlsOptions& mls = {});

/// The same from the window's samples themselves: column m of `x` / `y` is sample m's rest / deformed
/// position (a caller whose deformed positions are not a double matrix gathers them itself).
DeformationDescriptor windowDeformationDescriptor(const Window& window, const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& y,
                                                  int order, const Eigen::Vector3d* restNormal = nullptr,
                                                  const Eigen::Vector3d* deformedNormal = nullptr,
                                                  const kinematics::MlsOptions& mls = {});

}  // namespace deformation_enrichment::descriptors
