#include "deformation_enrichment/ros/tool_pose_sources.hpp"

#include <set>

#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::ros_layer {
namespace {

std::string stringMember(XmlRpc::XmlRpcValue& entry, const std::string& key, const std::string& where,
                         const std::string& fallback) {
  if (!entry.hasMember(key)) return fallback;
  if (entry[key].getType() != XmlRpc::XmlRpcValue::TypeString)
    throw InvalidInputError(where + ": '" + key + "' must be a string");
  return static_cast<std::string>(entry[key]);
}

}  // namespace

std::vector<ToolPoseSpec> toolPoseSpecs(XmlRpc::XmlRpcValue& list) {
  if (list.getType() != XmlRpc::XmlRpcValue::TypeArray)
    throw InvalidInputError("~tool_poses must be a list of {topic, id, type, tip_link}");
  std::vector<ToolPoseSpec> specs;
  std::set<std::string> topics, ids;
  for (int i = 0; i < list.size(); ++i) {
    const std::string where = "~tool_poses[" + std::to_string(i) + "]";
    XmlRpc::XmlRpcValue& entry = list[i];
    if (entry.getType() != XmlRpc::XmlRpcValue::TypeStruct) throw InvalidInputError(where + " is not a dictionary");
    for (const auto& [key, value] : entry) {
      (void)value;
      if (key != "topic" && key != "id" && key != "type" && key != "tip_link")
        throw InvalidInputError(where + ": unknown key '" + key + "' (expected topic, id, type, tip_link)");
    }
    ToolPoseSpec spec;
    spec.topic = stringMember(entry, "topic", where, "");
    if (spec.topic.empty()) throw InvalidInputError(where + " has no topic");
    spec.id = stringMember(entry, "id", where, spec.topic);
    const std::string type = stringMember(entry, "type", where, "pose");
    if (type == "transform") spec.type = ToolPoseSpec::Type::Transform;
    else if (type != "pose")
      throw InvalidInputError(where + ": type '" + type + "' is neither 'pose' (PoseStamped) nor 'transform' (TransformStamped)");
    spec.tipLink = stringMember(entry, "tip_link", where, "");
    if (!topics.insert(spec.topic).second) throw InvalidInputError(where + ": topic '" + spec.topic + "' is listed twice");
    if (!ids.insert(spec.id).second) throw InvalidInputError(where + ": tool id '" + spec.id + "' is listed twice");
    specs.push_back(spec);
  }
  return specs;
}

std::vector<ToolPoseSpec> defaultToolPoseSpecs(const std::string& id, const std::string& tipLink) {
  return {{"tool_pose", id, ToolPoseSpec::Type::Pose, tipLink}, {"tool_transform", id, ToolPoseSpec::Type::Transform, tipLink}};
}

}  // namespace deformation_enrichment::ros_layer
