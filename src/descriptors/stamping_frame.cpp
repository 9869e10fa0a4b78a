#include "deformation_enrichment/descriptors/stamping_frame.hpp"

#include <cmath>
#include <Eigen/Geometry>

#include "deformation_enrichment/error.hpp"

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
}  // namespace

StampingFrame stampingFrame(const Eigen::Vector3d& normal, const hermite::MomentList& rho,
                            const hermite::MomentList* mu, double relativeTolerance) {
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

  // Paper 000 §4.4: b_x along the tangential part of rho_1.
  const Eigen::Vector3d siteTangent = tangential(rho1, bz);
  const double siteScale = rho0 + rho1.norm();
  if (siteScale > 0.0 && siteTangent.norm() > relativeTolerance * siteScale)
    return assemble(bz, siteTangent, FrameRule::SiteMoment);

  if (mu != nullptr && !mu->empty()) {
    if (!mu->values().allFinite()) throw InvalidInputError("stamping frame: deformation moments are not finite");
    if (mu->channels() == 3 && mu->firstOrder() <= 1 && mu->lastOrder() >= 1) {
      Eigen::Matrix3d G;  // G(c, j): order-1 moment of u_bar_c along axis j
      for (int c = 0; c < 3; ++c) G.row(c) = mu->order(1, c).transpose();
      const Eigen::Vector3d shear = tangential((G + G.transpose()) * bz, bz);
      const double scale = hermite::norm(*mu);
      if (scale > 0.0 && shear.norm() > relativeTolerance * scale)
        return assemble(bz, shear, FrameRule::DeformationDirection);
    }
  }

  int axis = 0;  // the world axis least aligned with the normal
  for (int k = 1; k < 3; ++k)
    if (std::abs(bz[k]) < std::abs(bz[axis])) axis = k;
  return assemble(bz, Eigen::Vector3d::Unit(axis), FrameRule::Fixed);
}

}  // namespace deformation_enrichment::descriptors
