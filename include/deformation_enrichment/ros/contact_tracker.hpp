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
#include "deformation_enrichment/enrichment/tool_proximity.hpp"

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

  /// The contact of one tool from the pose of its tip link (enrichment::toolProximity against the state
  /// `surface`, with its triangles if given); its normal is the rest normal of the vertex nearest to it.
  /// Not in contact: the tool's contact is removed. Throws InvalidInputError like above.
  void updateFromToolPose(const geometry_msgs::PoseStamped& pose, const std::string& toolId,
                          const std::string& meshFrame, const Eigen::Matrix3Xf& surface,
                          const Eigen::Matrix3Xd& restNormals, double contactDistance, const enrichment::ToolTip& tip = {},
                          const Eigen::Matrix3Xi* triangles = nullptr);

  /// The tip link's pose in the pose's frame (enrichment::toolLinkPose's checks). Throws InvalidInputError.
  static Eigen::Isometry3d linkPose(const geometry_msgs::PoseStamped& pose, const std::string& toolId,
                                    const enrichment::ToolTip& tip);

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
