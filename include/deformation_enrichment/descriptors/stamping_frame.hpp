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
/// With `previousAxis` (the previous frame's b_x of the same contact) the shear direction takes the sign
/// that agrees with it: the sign of a nearly symmetric dent's shear is discretisation noise.
/// Fixed choice: `previousAxis` (the previous frame's b_x of the same contact, so a stream's frame does not
/// jump) projected on the tangent plane, else the world axis least aligned with b_z (lowest index on ties).
/// Continuity: a rule takes over smoothly (smoothstep) while its direction's length goes from one to two
/// tolerances, so b_x is a continuous function of the inputs; `rule` names the rule of largest weight.
/// Throws InvalidInputError for a non-finite normal or moments.
StampingFrame stampingFrame(const Eigen::Vector3d& normal, const hermite::MomentList& rho,
                            const hermite::MomentList* mu = nullptr, double relativeTolerance = 1e-3,
                            const Eigen::Vector3d* previousAxis = nullptr);

}  // namespace deformation_enrichment::descriptors
