#include "deformation_enrichment/descriptors/stamping_frame.hpp"

#include <cmath>
#include <Eigen/Geometry>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/smooth_ramp.hpp"

namespace deformation_enrichment::descriptors {

const char* toString(FrameRule rule) {
  switch (rule) {
    case FrameRule::SiteMoment: return "site_moment";
    case FrameRule::DeformationDirection: return "deformation_direction";
    case FrameRule::Fixed: return "fixed";
  }
  return "fixed";
}

namespace {
Eigen::Vector3d tangential(const Eigen::Vector3d& v, const Eigen::Vector3d& n) { return v - v.dot(n) * n; }

StampingFrame assemble(const Eigen::Vector3d& bz, const Eigen::Vector3d& tangent, FrameRule rule) {
  StampingFrame frame;
  const Eigen::Vector3d bx = tangential(tangent, bz).normalized();
  frame.B.col(0) = bx;
  frame.B.col(1) = bz.cross(bx);  // b_y = b_z x b_x
  frame.B.col(2) = bz;
  frame.rule = rule;
  return frame;
}

// The last resort: the previous frame's b_x (continuity over time), else the world axis least aligned with
// the normal (lowest index on ties).
Eigen::Vector3d fallbackTangent(const Eigen::Vector3d& bz, const Eigen::Vector3d* previousAxis) {
  if (previousAxis != nullptr && previousAxis->allFinite()) {
    const Eigen::Vector3d t = tangential(*previousAxis, bz);
    if (t.norm() > 0.1 * previousAxis->norm()) return t.normalized();
  }
  int axis = 0;
  for (int k = 1; k < 3; ++k)
    if (std::abs(bz[k]) < std::abs(bz[axis])) axis = k;
  return tangential(Eigen::Vector3d::Unit(axis), bz).normalized();
}

// Shear direction of the deformation (see the header); zero when mu has no usable order 1.
Eigen::Vector3d shearDirection(const hermite::MomentList* mu, const Eigen::Vector3d& bz, double& scale) {
  scale = 0.0;
  if (mu == nullptr || mu->empty()) return Eigen::Vector3d::Zero();
  if (!mu->values().allFinite()) throw InvalidInputError("stamping frame: deformation moments are not finite");
  if (mu->channels() != 3 || mu->firstOrder() > 1 || mu->lastOrder() < 1) return Eigen::Vector3d::Zero();
  Eigen::Matrix3d G;  // G(c, j): order-1 moment of u_bar_c along axis j
  for (int c = 0; c < 3; ++c) G.row(c) = mu->order(1, c).transpose();
  scale = hermite::norm(*mu);
  return tangential((G + G.transpose()) * bz, bz);
}
}  // namespace

StampingFrame stampingFrame(const Eigen::Vector3d& normal, const hermite::MomentList& rho,
                            const hermite::MomentList* mu, double relativeTolerance, const Eigen::Vector3d* previousAxis) {
  if (!normal.allFinite()) throw InvalidInputError("stamping frame: normal is not finite");
  if (!rho.values().allFinite()) throw InvalidInputError("stamping frame: site moments are not finite");
  if (rho.firstOrder() > 1 || rho.lastOrder() < 1 || rho.channels() != 1)
    throw InvalidInputError("stamping frame: site moments must contain order 1");
  const Eigen::Vector3d rho1 = rho.order(1);
  const double rho0 = rho.firstOrder() == 0 ? std::abs(rho.order(0)[0]) : 0.0;

  Eigen::Vector3d bz;
  if (normal.norm() > 0.0) bz = normal.normalized();
  else if (rho1.norm() > 0.0) bz = -rho1.normalized();  // rho_1 points towards the material
  else bz = Eigen::Vector3d::UnitZ();

  // Paper 000 §4.4: b_x along the tangential part of rho_1; then the shear; then the fallback, each taking
  // over smoothly (from one to two tolerances) as the one before loses its direction.
  const Eigen::Vector3d siteTangent = tangential(rho1, bz);
  const double site = smoothRamp(siteTangent.norm(), relativeTolerance * (rho0 + rho1.norm()));
  double muScale = 0.0;
  Eigen::Vector3d shear = shearDirection(mu, bz, muScale);
  // The shear of a nearly symmetric dent has a sign set by discretisation noise: a stream keeps the sign of
  // its previous frame (without history, the sign as computed, as the examples were described).
  if (previousAxis != nullptr && shear.dot(*previousAxis) < 0.0) shear = -shear;
  const double deformation = smoothRamp(shear.norm(), relativeTolerance * muScale);
  const Eigen::Vector3d fallback = fallbackTangent(bz, previousAxis);
  const auto unit = [](const Eigen::Vector3d& v) { return v.norm() > 0.0 ? Eigen::Vector3d(v.normalized()) : v; };
  const Eigen::Vector3d tangent =
      site * unit(siteTangent) + (1.0 - site) * (deformation * unit(shear) + (1.0 - deformation) * fallback);
  const FrameRule rule = site >= 0.5 ? FrameRule::SiteMoment
                         : deformation >= 0.5 ? FrameRule::DeformationDirection
                                              : FrameRule::Fixed;
  // Opposite directions of equal weight cancel: the fallback decides then.
  return assemble(bz, tangential(tangent, bz).norm() > 1e-6 ? tangent : fallback, rule);
}

}  // namespace deformation_enrichment::descriptors
