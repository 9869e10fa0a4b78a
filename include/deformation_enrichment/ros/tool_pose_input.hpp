#pragma once
// The enrichment node's tool pose topics (~tool_poses, or tool_pose and tool_transform): subscribes each, keeps
// each tool's latest pose, and resolves the kept poses against a mesh state into contacts. Each tool's tip is
// the collision geometry of its URDF link, or a point. Thread-safe: poses arrive on any callback thread.
#include <geometry_msgs/PoseStamped.h>
#include <ros/node_handle.h>

#include <diagnostic_updater/diagnostic_updater.h>

#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "deformation_enrichment/enrichment/enrichment_session.hpp"
#include "deformation_enrichment/enrichment/tool_tip.hpp"
#include "deformation_enrichment/ros/contact_tracker.hpp"
#include "deformation_enrichment/ros/tool_pose_sources.hpp"

namespace deformation_enrichment::ros_layer {

class ToolPoseInput {
public:
  /// Called for every pose dropped: (input topic, reason, detail).
  using Reject = std::function<void(const std::string&, const std::string&, const std::string&)>;

  /// Subscribes every spec's topic on `nh`; tips from `urdf` (robot_description) where a spec names a link
  /// (without a usable URDF: a point tip, logged).
  ToolPoseInput(ros::NodeHandle nh, const std::vector<ToolPoseSpec>& specs, const std::optional<std::string>& urdf,
                Reject reject);

  /// Resolves the kept poses against the state `positions` (stamped `stamp`, frame `meshFrame`) of `rest`
  /// into `contacts`, so a contact lies on the state it goes with however poses and states interleave. A pose
  /// stamped over a second after the state (a rosbag started over) is dropped and forgotten.
  void resolve(const ros::Time& stamp, const std::string& meshFrame, const Eigen::Matrix3Xf& positions,
               const enrichment::RestSurface& rest, double contactDistance, ContactTracker& contacts);

  /// Each tool's tip as used, for diagnostics.
  void report(diagnostic_updater::DiagnosticStatusWrapper& status) const;

private:
  struct Source {
    ToolPoseSpec spec;
    enrichment::ToolTip tip;
    std::string tipStatus;  ///< the tip's description, or why the URDF tip was not used
    ros::Subscriber subscriber;
  };
  /// Checks a tool's pose and keeps it as the tool's latest (a bad one is rejected).
  void keep(const geometry_msgs::PoseStamped& pose, const Source& source);

  Reject reject_;
  std::vector<std::unique_ptr<Source>> sources_;  // stable addresses: the callbacks hold them
  std::mutex mutex_;                              // guards poses_
  std::map<std::string, std::pair<geometry_msgs::PoseStamped, const Source*>> poses_;  // by tool id
};

}  // namespace deformation_enrichment::ros_layer
