#pragma once
// The tool pose topics of the enrichment node (~tool_poses): one entry per tool, each naming its topic, the
// tool id its contacts carry, the message type (CRTK measured_cp is geometry_msgs/PoseStamped from dVRK 2.1
// on, geometry_msgs/TransformStamped in dVRK <= 2.0 and AMBF before 2022) and its URDF tip link.
#include <xmlrpcpp/XmlRpcValue.h>

#include <string>
#include <vector>

namespace deformation_enrichment::ros_layer {

struct ToolPoseSpec {
  enum class Type { Pose, Transform };
  std::string topic;    ///< resolved in the node's namespace (remappable)
  std::string id;       ///< tool id of the contacts derived from it
  Type type = Type::Pose;
  std::string tipLink;  ///< URDF link of the tip's collision geometry; empty: a point tip
};

/// The entries of ~tool_poses: a list of {topic, id, type: pose | transform (default pose), tip_link
/// (default "")}; id defaults to the topic. Throws InvalidInputError naming the entry: not a list, an entry
/// that is not a dictionary, a missing or empty topic, a value of the wrong type, an unknown type or key,
/// two entries with the same topic or the same id.
std::vector<ToolPoseSpec> toolPoseSpecs(XmlRpc::XmlRpcValue& list);

/// The node's tool poses without ~tool_poses: topics tool_pose (PoseStamped) and tool_transform
/// (TransformStamped), both of the one tool `id` with tip `tipLink`.
std::vector<ToolPoseSpec> defaultToolPoseSpecs(const std::string& id, const std::string& tipLink);

}  // namespace deformation_enrichment::ros_layer
