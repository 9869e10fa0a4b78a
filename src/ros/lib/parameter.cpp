#include "deformation_enrichment/ros/parameter.hpp"

#include <ros/console.h>

#include <cmath>
#include <limits>

#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::ros_layer {

using Type = XmlRpc::XmlRpcValue::Type;

template <>
std::optional<double> parameterAs<double>(XmlRpc::XmlRpcValue& value) {
  if (value.getType() == Type::TypeDouble) return static_cast<double>(value);
  if (value.getType() == Type::TypeInt) return static_cast<double>(static_cast<int>(value));
  return std::nullopt;
}

template <>
std::optional<int> parameterAs<int>(XmlRpc::XmlRpcValue& value) {
  if (value.getType() == Type::TypeInt) return static_cast<int>(value);
  if (value.getType() == Type::TypeDouble) {  // 4.0 from a YAML file that wrote the number as a double
    const double v = static_cast<double>(value);
    if (std::floor(v) == v && std::abs(v) <= std::numeric_limits<int>::max()) return static_cast<int>(v);
  }
  return std::nullopt;
}

template <>
std::optional<bool> parameterAs<bool>(XmlRpc::XmlRpcValue& value) {
  if (value.getType() == Type::TypeBoolean) return static_cast<bool>(value);
  return std::nullopt;
}

template <>
std::optional<std::string> parameterAs<std::string>(XmlRpc::XmlRpcValue& value) {
  if (value.getType() == Type::TypeString) return static_cast<std::string>(value);
  return std::nullopt;
}

template <>
const char* parameterKind<double>() { return "a number"; }
template <>
const char* parameterKind<int>() { return "a whole number"; }
template <>
const char* parameterKind<bool>() { return "true or false"; }
template <>
const char* parameterKind<std::string>() { return "a string"; }

std::string describeParameter(XmlRpc::XmlRpcValue& value) {
  std::ostringstream text;
  switch (value.getType()) {
    case Type::TypeDouble: text << static_cast<double>(value); break;
    case Type::TypeInt: text << static_cast<int>(value); break;
    case Type::TypeBoolean: text << std::boolalpha << static_cast<bool>(value); break;
    case Type::TypeString: text << '"' << static_cast<std::string>(value) << '"'; break;
    case Type::TypeArray: text << "a list of " << value.size(); break;
    case Type::TypeStruct: text << "a dictionary"; break;
    default: text << "a value of XML-RPC type " << static_cast<int>(value.getType()); break;
  }
  return text.str();
}

void throwWrongType(const ros::NodeHandle& nh, const std::string& name, const std::string& expected, const std::string& given) {
  throw InvalidInputError(nh.resolveName(name) + " must be " + expected + ", got " + given);
}

void ParameterReader::refuse(const std::string& name, const std::string& expected, const std::string& given,
                             const std::string& fallback) {
  ROS_ERROR("%s must be %s, got %s: using %s", nh_.resolveName(name).c_str(), expected.c_str(), given.c_str(), fallback.c_str());
  refused_.push_back(name + " (" + given + ")");
}

}  // namespace deformation_enrichment::ros_layer
