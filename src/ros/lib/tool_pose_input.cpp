#include "deformation_enrichment/ros/tool_pose_input.hpp"

#include <geometry_msgs/TransformStamped.h>
#include <ros/console.h>

#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::ros_layer {
namespace {

// `link`'s collision geometry from the URDF (a point tip for an empty link, or without a usable URDF,
// logged); `status` describes which.
enrichment::ToolTip loadTip(const std::string& link, const std::optional<std::string>& urdf, std::string& status) {
  if (link.empty()) {
    status = enrichment::ToolTip().description();
    return {};
  }
  if (!urdf) {
    status = "point (no robot_description for tip link '" + link + "')";
    ROS_WARN("tip link '%s' is set but there is no robot_description: the tool pose position is the tip", link.c_str());
    return {};
  }
  try {
    enrichment::ToolTip tip = enrichment::toolTipFromUrdf(*urdf, link);
    status = tip.description();
    ROS_INFO("tool tip: %s", status.c_str());
    return tip;
  } catch (const Error& e) {
    status = std::string("point (robot_description rejected: ") + e.what() + ")";
    ROS_ERROR("tool tip from robot_description rejected: %s; the tool pose position is the tip", e.what());
    return {};
  }
}

}  // namespace

ToolPoseInput::ToolPoseInput(ros::NodeHandle nh, const std::vector<ToolPoseSpec>& specs,
                             const std::optional<std::string>& urdf, Reject reject)
    : reject_(std::move(reject)) {
  for (const ToolPoseSpec& spec : specs) {
    auto source = std::make_unique<Source>();
    source->spec = spec;
    source->tip = loadTip(spec.tipLink, urdf, source->tipStatus);
    const Source* self = source.get();
    if (spec.type == ToolPoseSpec::Type::Pose) {
      source->subscriber = nh.subscribe<geometry_msgs::PoseStamped>(
          spec.topic, 10, [this, self](const geometry_msgs::PoseStampedConstPtr& message) { keep(*message, *self); });
    } else {
      source->subscriber = nh.subscribe<geometry_msgs::TransformStamped>(
          spec.topic, 10, [this, self](const geometry_msgs::TransformStampedConstPtr& message) {
            geometry_msgs::PoseStamped pose;
            pose.header = message->header;  // the transform's parent frame is the pose's frame
            pose.pose.position.x = message->transform.translation.x;
            pose.pose.position.y = message->transform.translation.y;
            pose.pose.position.z = message->transform.translation.z;
            pose.pose.orientation = message->transform.rotation;
            keep(pose, *self);
          });
    }
    ROS_INFO("tool '%s' from %s (%s)", spec.id.c_str(), source->subscriber.getTopic().c_str(),
             spec.type == ToolPoseSpec::Type::Pose ? "geometry_msgs/PoseStamped" : "geometry_msgs/TransformStamped");
    sources_.push_back(std::move(source));
  }
}

void ToolPoseInput::keep(const geometry_msgs::PoseStamped& pose, const Source& source) {
  try {
    ContactTracker::linkPose(pose, source.spec.id, source.tip);
  } catch (const Error& e) {
    return reject_(source.spec.topic, "invalid pose", e.what());
  }
  std::lock_guard<std::mutex> lock(mutex_);
  poses_[source.spec.id] = {pose, &source};
}

void ToolPoseInput::resolve(const ros::Time& stamp, const std::string& meshFrame, const Eigen::Matrix3Xf& positions,
                            const enrichment::RestSurface& rest, double contactDistance, ContactTracker& contacts) {
  std::lock_guard<std::mutex> lock(mutex_);
  for (auto it = poses_.begin(); it != poses_.end();) {
    const auto& [pose, source] = it->second;
    if (pose.header.stamp > stamp + ros::Duration(1.0)) {
      reject_(source->spec.topic, "pose stamped over 1 s after the mesh state",
              "pose " + std::to_string(pose.header.stamp.toSec()) + " s, state " + std::to_string(stamp.toSec()) + " s");
      it = poses_.erase(it);
      continue;
    }
    try {
      // A URDF tip is measured against the triangles (exact, 1.39 ms at 100k vertices, bench_tool_contact);
      // a point tip against the vertices (0.33 ms), its contact being the tip itself.
      contacts.updateFromToolPose(pose, source->spec.id, meshFrame, positions, rest.normals, contactDistance, source->tip,
                                  source->tip.isPoint() ? nullptr : &rest.geometry.surface.triangles);
    } catch (const Error& e) {
      reject_(source->spec.topic, "no contact from this pose", e.what());
    }
    ++it;
  }
}

void ToolPoseInput::report(diagnostic_updater::DiagnosticStatusWrapper& status) const {
  for (const auto& source : sources_) status.add("tool tip of " + source->spec.id + " on " + source->spec.topic, source->tipStatus);
}

}  // namespace deformation_enrichment::ros_layer
