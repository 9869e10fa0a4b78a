#pragma once
// Private parameters read with their type checked. roscpp's NodeHandle::param returns the fallback
// silently when the value has another type (rate: "fast", an order of 2.5, a flag given as "false"), so a
// typo in a launch file would pass unnoticed. Here a value of the wrong type is refused with what was
// given: a node that keeps running logs it and keeps the fallback (parameter), a node that stops on a bad
// setting throws (requiredTypeParameter).
#include <ros/node_handle.h>
#include <xmlrpcpp/XmlRpcValue.h>

#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace deformation_enrichment::ros_layer {

/// The value as a T, or nothing when it is of another type: a double also takes an integer, an int a
/// whole number (a double without a fraction too), a bool only true or false, a string only a string.
template <typename T>
std::optional<T> parameterAs(XmlRpc::XmlRpcValue& value);

/// What a value is, for a message: the number, the quoted text, or its kind (a list, a dictionary).
std::string describeParameter(XmlRpc::XmlRpcValue& value);

/// What a T is, for a message: "a number", "a whole number", "true or false", "a string".
template <typename T>
const char* parameterKind();

/// Throws InvalidInputError: ~name must be `expected`, got `given`.
[[noreturn]] void throwWrongType(const ros::NodeHandle& nh, const std::string& name, const std::string& expected,
                                 const std::string& given);

/// ~name as a T, the fallback when it is not set; throws InvalidInputError naming the parameter, the type
/// expected and the value given when it is of another type.
template <typename T>
T requiredTypeParameter(const ros::NodeHandle& nh, const std::string& name, T fallback) {
  XmlRpc::XmlRpcValue value;
  if (!nh.getParam(name, value)) return fallback;
  if (const std::optional<T> typed = parameterAs<T>(value)) return *typed;
  throwWrongType(nh, name, parameterKind<T>(), describeParameter(value));
}

/// Reads private parameters, logging each value refused (ROS_ERROR: the parameter, what it must be, the
/// value given and the fallback used) and keeping a list of them, e.g. for /diagnostics.
class ParameterReader {
public:
  explicit ParameterReader(const ros::NodeHandle& nh) : nh_(nh) {}

  const ros::NodeHandle& nodeHandle() const { return nh_; }

  /// ~name as a T that `valid` accepts; the fallback when it is not set, or when it is of another type or
  /// `valid` refuses it (then logged, `expected` naming the range, e.g. ">= 0", and ~name set to the fallback).
  template <typename T, typename Valid>
  T operator()(const std::string& name, T fallback, Valid valid, const std::string& expected) {
    XmlRpc::XmlRpcValue value;
    if (!nh_.getParam(name, value)) return fallback;
    const std::optional<T> typed = parameterAs<T>(value);
    if (typed && valid(*typed)) return *typed;
    std::ostringstream text;
    text << std::boolalpha << fallback;
    refuse(name, expected.empty() ? parameterKind<T>() : std::string(parameterKind<T>()) + ", " + expected,
           describeParameter(value), text.str());
    // The server then holds the value in use: a reconfigure server starts from it (it would clamp the
    // refused value into its range and apply that instead of the fallback).
    nh_.setParam(name, fallback);
    return fallback;
  }

  /// The same with every value of the type accepted.
  template <typename T>
  T operator()(const std::string& name, T fallback) {
    return (*this)(name, fallback, [](const T&) { return true; }, "");
  }

  /// Logs a value refused for ~name and lists it.
  void refuse(const std::string& name, const std::string& expected, const std::string& given, const std::string& fallback);

  /// The values refused so far, each "name (value given)".
  const std::vector<std::string>& refused() const { return refused_; }

private:
  ros::NodeHandle nh_;
  std::vector<std::string> refused_;
};

/// ~name read by a ParameterReader of its own (logged when refused).
template <typename T, typename Valid>
T parameter(const ros::NodeHandle& nh, const std::string& name, T fallback, Valid valid, const std::string& expected) {
  ParameterReader read(nh);
  return read(name, fallback, valid, expected);
}

template <typename T>
T parameter(const ros::NodeHandle& nh, const std::string& name, T fallback) {
  ParameterReader read(nh);
  return read(name, fallback);
}

}  // namespace deformation_enrichment::ros_layer
