#pragma once
// Stamping frame B = [b_x b_y b_z] of [Seiler14 §4.4]: b_z the surface normal at p, b_x the tangential part of
// the first density moment rho_1, b_y = b_z x b_x. Where rho_1 has no tangential direction (flat regions,
// symmetric sites) docs/design.md §4 asks for fallbacks: the dominant tangential direction of the deformation,
// then a fixed deterministic choice. The result is always a proper rotation, never NaN.
#include <Eigen/Core>

#include "deformation_enrichment/hermite/moment_list.hpp"

namespace deformation_enrichment::descriptors {

/// Which rule fixed b_x.
enum class FrameRule { SiteMoment, DeformationDirection, Fixed };
const char* toString(FrameRule rule);

struct StampingFrame {
  Eigen::Matrix3d B = Eigen::Matrix3d::Identity();  ///< columns b_x, b_y, b_z (world axes)
  FrameRule rule = FrameRule::Fixed;
};

/// `normal` need not be unit length; a zero normal falls back to -rho_1 (rho_1 points into the material),
/// then to +z. `rho` holds order 1 (world axes). `mu` (orders from 1, 3 channels, world axes) may be null.
/// A tangential direction counts when its length exceeds `relativeTolerance` times the scale of the moments
/// it comes from (|rho_0| + |rho_1| for rho, |mu| for the deformation).
/// Deformation direction: the tangential part of (G + G^T) n with G the order-1 displacement moment
/// (G_cj ~ d u_bar_c / d x_j): the direction in which the surface is sheared.
/// Fixed choice: the world axis least aligned with b_z (lowest index on ties), projected on the tangent plane.
/// Throws InvalidInputError for a non-finite normal or moments.
StampingFrame stampingFrame(const Eigen::Vector3d& normal, const hermite::MomentList& rho,
                            const hermite::MomentList* mu = nullptr, double relativeTolerance = 1e-3);

}  // namespace deformation_enrichment::descriptors
