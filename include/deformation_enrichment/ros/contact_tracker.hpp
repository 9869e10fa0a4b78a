#pragma once
// Tool contacts in the mesh frame, from ToolContactArray messages and/or tool poses (proximity to the
// surface), with staleness and rosbag-loop handling.
#include <geometry_msgs/PoseStamped.h>
#include <tf2_ros/buffer.h>

#include <Eigen/Geometry>
#include <map>
#include <string>
#include <vector>

#include "deformation_enrichment/ToolContactArray.h"
#include "deformation_enrichment/ros/tool_tip.hpp"

namespace deformation_enrichment::ros_layer {

struct TrackedContact {
  std::string toolId;
  Eigen::Vector3d position;  ///< in the mesh frame [m]
  Eigen::Vector3d normal;    ///< unit outward normal in the mesh frame (zero if unknown)
  double force = 0.0;        ///< [N]
  ros::Time stamp;
};

class ContactTracker {
public:
  ContactTracker(const tf2_ros::Buffer& tf, ros::Duration staleAfter) : tf_(tf), staleAfter_(staleAfter) {}

  /// Replaces all array-sourced contacts. Throws InvalidInputError naming the problem (non-finite values,
  /// a frame tf cannot transform); then the previous contacts stay.
  void updateFromArray(const ToolContactArray& message, const std::string& meshFrame);

  /// Derives the contact of one tool from the pose of its tip link: in contact when the surface comes
  /// within `contactDistance` of the tip's surface (signed distance, so also when it cuts into the tip); the
  /// contact is the surface point closest to (deepest in) the tip, its normal the rest normal of the
  /// surface vertex nearest to it. A point tip is the pose's position. Without `triangles`, the surface is
  /// its vertices, and a point tip's contact is the tip itself (ContactEnricher places it on the surface). With `triangles` (the surface's
  /// topology) the surface is its triangles: every triangle with a vertex within contactDistance + its
  /// longest edge of the tip (a superset of those that can be within contactDistance, the signed distance
  /// being 1-Lipschitz) is measured exactly. Throws like above.
  void updateFromToolPose(const geometry_msgs::PoseStamped& pose, const std::string& toolId,
                          const std::string& meshFrame, const Eigen::Matrix3Xf& surface,
                          const Eigen::Matrix3Xd& restNormals, double contactDistance, const ToolTip& tip = {},
                          const Eigen::Matrix3Xi* triangles = nullptr);

  /// The tip link's pose in the pose's frame, after checking the pose: finite, and a unit quaternion for a
  /// shaped tip (a point tip ignores the orientation). Throws InvalidInputError naming the problem.
  static Eigen::Isometry3d linkPose(const geometry_msgs::PoseStamped& pose, const std::string& toolId, const ToolTip& tip);

  /// Contacts in contact and not older than the staleness limit at `now`. A clock that jumped backwards
  /// (a rosbag loop) clears everything.
  std::vector<TrackedContact> active(const ros::Time& now);

private:
  Eigen::Isometry3d toMeshFrame(const std_msgs::Header& header, const std::string& meshFrame) const;

  const tf2_ros::Buffer& tf_;
  ros::Duration staleAfter_;
  std::map<std::string, TrackedContact> contacts_;  // by tool id; only tools in contact
  Eigen::ArrayXf vertexBound_;                      // scratch: lower bound of the tip distance per vertex
  ros::Time latestStamp_;
};

}  // namespace deformation_enrichment::ros_layer
