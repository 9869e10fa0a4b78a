// ~tool_poses without a master: the entries the node subscribes, their defaults, and a clear error for each
// kind of unusable entry. Linked into test_enrichment_knobs.
#include <gtest/gtest.h>

#include <string>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/ros/tool_pose_sources.hpp"

namespace de = deformation_enrichment;
using de::ros_layer::ToolPoseSpec;

namespace {

XmlRpc::XmlRpcValue entry(std::initializer_list<std::pair<std::string, XmlRpc::XmlRpcValue>> members) {
  XmlRpc::XmlRpcValue value;
  value.begin();  // an empty struct even without members
  for (const auto& [key, member] : members) value[key] = member;
  return value;
}

XmlRpc::XmlRpcValue list(std::initializer_list<XmlRpc::XmlRpcValue> entries) {
  XmlRpc::XmlRpcValue value;
  value.setSize(static_cast<int>(entries.size()));
  int i = 0;
  for (const auto& e : entries) value[i++] = e;
  return value;
}

void expectRefused(XmlRpc::XmlRpcValue value, const std::string& fragment) {
  try {
    de::ros_layer::toolPoseSpecs(value);
    ADD_FAILURE() << "accepted; expected an error containing '" << fragment << "'";
  } catch (const de::InvalidInputError& e) {
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

TEST(ToolPoseSources, EntriesWithTheirDefaults) {
  XmlRpc::XmlRpcValue value = list({entry({{"topic", "/PSM1/measured_cp"}, {"id", "PSM1"}, {"tip_link", "tip"}}),
                                    entry({{"topic", "/PSM2/measured_cp"}, {"type", "transform"}})});
  const auto specs = de::ros_layer::toolPoseSpecs(value);
  ASSERT_EQ(specs.size(), 2u);
  EXPECT_EQ(specs[0].topic, "/PSM1/measured_cp");
  EXPECT_EQ(specs[0].id, "PSM1");
  EXPECT_EQ(specs[0].type, ToolPoseSpec::Type::Pose);
  EXPECT_EQ(specs[0].tipLink, "tip");
  EXPECT_EQ(specs[1].id, "/PSM2/measured_cp") << "the id defaults to the topic";
  EXPECT_EQ(specs[1].type, ToolPoseSpec::Type::Transform);
  EXPECT_EQ(specs[1].tipLink, "");
  const auto defaults = de::ros_layer::defaultToolPoseSpecs("tool", "link");
  ASSERT_EQ(defaults.size(), 2u);
  EXPECT_EQ(defaults[0].topic, "tool_pose");
  EXPECT_EQ(defaults[1].topic, "tool_transform");
  EXPECT_EQ(defaults[1].type, ToolPoseSpec::Type::Transform);
  EXPECT_EQ(defaults[0].id, "tool");
  EXPECT_EQ(defaults[1].tipLink, "link");
}

TEST(ToolPoseSources, UnusableEntriesAreNamed) {
  expectRefused(XmlRpc::XmlRpcValue("PSM1"), "must be a list");
  expectRefused(list({XmlRpc::XmlRpcValue(3)}), "~tool_poses[0] is not a dictionary");
  expectRefused(list({entry({{"id", "PSM1"}})}), "~tool_poses[0] has no topic");
  expectRefused(list({entry({{"topic", 7}})}), "'topic' must be a string");
  expectRefused(list({entry({{"topic", "a"}, {"type", "odometry"}})}), "type 'odometry'");
  expectRefused(list({entry({{"topic", "a"}, {"frame", "x"}})}), "unknown key 'frame'");
  expectRefused(list({entry({{"topic", "a"}}), entry({{"topic", "a"}, {"id", "b"}})}), "~tool_poses[1]: topic 'a' is listed twice");
  expectRefused(list({entry({{"topic", "a"}, {"id", "T"}}), entry({{"topic", "b"}, {"id", "T"}})}), "tool id 'T' is listed twice");
}

}  // namespace
