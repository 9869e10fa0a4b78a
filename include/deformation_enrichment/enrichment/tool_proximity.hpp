#pragma once
// Where a tool touches the surface, from the pose of its tip link (docs/design.md §3): the tool is in contact
// when the surface comes within a contact distance of the tip's surface (signed distance, so also when the
// surface cuts into the tip), at the surface point closest to (deepest in) the tip.
#include <Eigen/Geometry>
#include <string>

#include "deformation_enrichment/enrichment/tool_tip.hpp"

namespace deformation_enrichment::enrichment {

/// The tip link's pose from a position and an orientation: both finite, and a unit quaternion (within
/// 1e-3) for a shaped tip; a point tip ignores the orientation (a position-only source may leave it zero).
/// Throws InvalidInputError naming the tool and the problem.
Eigen::Isometry3d toolLinkPose(const Eigen::Vector3d& position, const Eigen::Quaterniond& orientation,
                               const ToolTip& tip, const std::string& toolId);

struct ToolProximity {
  bool inContact = false;
  double distance = 0.0;                           ///< signed distance of the surface to the tip (m)
  Eigen::Vector3d point = Eigen::Vector3d::Zero();  ///< the contact (mesh frame)
  Eigen::Index nearestVertex = 0;                  ///< the surface vertex nearest to the contact
};

/// The contact of the tip at `linkToMesh` with the surface `vertices` (mesh frame). Lower bounds from the
/// tip's bounding ball skip most exact distances. Without `triangles` the surface is its vertices, and a
/// point tip's contact is the tip itself (ContactEnricher places it on the surface, so it does not jump
/// from vertex to vertex as the tool slides). With `triangles` (the surface's topology) the surface is its
/// triangles: every triangle with a vertex within contactDistance + its longest edge of the tip (a superset
/// of those that can be within contactDistance, the signed distance being 1-Lipschitz) is measured exactly.
/// `scratch` is reused between calls. Throws InvalidInputError for no vertices or triangle indices out of
/// range.
ToolProximity toolProximity(const Eigen::Isometry3d& linkToMesh, const ToolTip& tip, const Eigen::Matrix3Xf& vertices,
                            double contactDistance, const Eigen::Matrix3Xi* triangles, Eigen::ArrayXf& scratch);

}  // namespace deformation_enrichment::enrichment
