// Typed parameter values without a master: which XML-RPC values each type takes, and how a refused one is
// described. Linked into test_enrichment_knobs.
#include <gtest/gtest.h>

#include <optional>
#include <string>

#include "deformation_enrichment/ros/parameter.hpp"

namespace rl = deformation_enrichment::ros_layer;

namespace {

template <typename T>
std::optional<T> as(XmlRpc::XmlRpcValue value) {
  return rl::parameterAs<T>(value);
}

std::string described(XmlRpc::XmlRpcValue value) { return rl::describeParameter(value); }

}  // namespace

TEST(Parameter, ANumberTakesDoublesAndIntegersOnly) {
  EXPECT_EQ(as<double>(XmlRpc::XmlRpcValue(2.5)), 2.5);
  EXPECT_EQ(as<double>(XmlRpc::XmlRpcValue(3)), 3.0);
  EXPECT_FALSE(as<double>(XmlRpc::XmlRpcValue("2.5")));
  EXPECT_FALSE(as<double>(XmlRpc::XmlRpcValue(true)));
}

TEST(Parameter, AWholeNumberTakesIntegersAndDoublesWithoutAFraction) {
  EXPECT_EQ(as<int>(XmlRpc::XmlRpcValue(4)), 4);
  EXPECT_EQ(as<int>(XmlRpc::XmlRpcValue(4.0)), 4);
  EXPECT_FALSE(as<int>(XmlRpc::XmlRpcValue(2.5)));
  EXPECT_FALSE(as<int>(XmlRpc::XmlRpcValue(1e12)));  // beyond int
  EXPECT_FALSE(as<int>(XmlRpc::XmlRpcValue("4")));
}

TEST(Parameter, FlagsAndTextsTakeTheirOwnTypeOnly) {
  EXPECT_EQ(as<bool>(XmlRpc::XmlRpcValue(false)), false);
  EXPECT_FALSE(as<bool>(XmlRpc::XmlRpcValue("false")));
  EXPECT_FALSE(as<bool>(XmlRpc::XmlRpcValue(0)));
  EXPECT_EQ(as<std::string>(XmlRpc::XmlRpcValue("paper")), "paper");
  EXPECT_FALSE(as<std::string>(XmlRpc::XmlRpcValue(3)));
}

TEST(Parameter, ARefusedValueIsDescribedAsGiven) {
  EXPECT_EQ(described(XmlRpc::XmlRpcValue(2.5)), "2.5");
  EXPECT_EQ(described(XmlRpc::XmlRpcValue(-1)), "-1");
  EXPECT_EQ(described(XmlRpc::XmlRpcValue(true)), "true");
  EXPECT_EQ(described(XmlRpc::XmlRpcValue("abc")), "\"abc\"");
  XmlRpc::XmlRpcValue list;
  list.setSize(2);
  list[0] = 1;
  list[1] = 2;
  EXPECT_EQ(described(list), "a list of 2");
}
