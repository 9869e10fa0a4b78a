#include "deformation_enrichment/ros/coarse_bag.hpp"

#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <std_msgs/String.h>

#include <filesystem>
#include <map>
#include <optional>
#include <sstream>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/number_parsing.hpp"
#include "deformation_enrichment/ros/conversions.hpp"

namespace deformation_enrichment::ros_layer {
namespace {

std::string planText(const std::vector<acquisition::PlanEntry>& plan) {
  std::ostringstream out;
  acquisition::writePlan(out, plan);
  return out.str();
}

// "begin 3" / "end 3" -> ("begin", 3); nullopt for anything else.
std::optional<std::pair<std::string, std::size_t>> marker(const std::string& text) {
  const std::size_t space = text.find(' ');
  if (space == std::string::npos) return std::nullopt;
  const std::string word = text.substr(0, space);
  const std::optional<long> line = parseInteger(text.substr(space + 1));
  if ((word != "begin" && word != "end") || !line || *line < 0) return std::nullopt;
  return std::make_pair(word, static_cast<std::size_t>(*line));
}

const std::map<std::string, std::string>& expectedTypes() {
  static const std::map<std::string, std::string> types{{kPlanTopic, "std_msgs/String"},
                                                        {kSimulatorTopic, "std_msgs/String"},
                                                        {kInteractionTopic, "std_msgs/String"},
                                                        {kCommandTopic, "geometry_msgs/PoseStamped"},
                                                        {kStateTopic, "sensor_msgs/PointCloud2"}};
  return types;
}

// What the reader gathers while walking the bag in time order.
struct Walk {
  const std::string& path;
  long vertices;
  acquisition::RecordedCoarse recorded;
  std::optional<std::size_t> open;  // the interaction begun and not yet ended
  std::optional<Eigen::Matrix3Xd> last;
  std::string commandFrame;
  std::set<std::size_t> completed;

  [[noreturn]] void fail(const std::string& problem) const { throw InvalidInputError(path + ": " + problem); }
  std::string lineName(std::size_t line) const { return "plan line " + std::to_string(line + 1); }

  void interaction(const std::string& text) {
    const auto m = marker(text);
    if (!m) fail("'" + text + "' on " + kInteractionTopic + " is not 'begin <line>' or 'end <line>'");
    if (m->second >= recorded.plan.size())
      fail(lineName(m->second) + " is beyond the recorded plan of " + std::to_string(recorded.plan.size()) + " lines");
    if (m->first == "begin") {
      if (open) fail(lineName(*open) + " was begun and not ended before " + lineName(m->second) + " began");
      open = m->second;
      last.reset();
      return;
    }
    if (open != m->second) fail(lineName(m->second) + " ended without being begun");
    if (!last) fail(lineName(m->second) + " ended without a state");
    recorded.settled[m->second] = *last;
    completed.insert(m->second);
    open.reset();
  }

  void state(const sensor_msgs::PointCloud2& cloud) {
    if (vertices < 0) {  // a resumed writer counts complete interactions only
      last = Eigen::Matrix3Xd();
      return;
    }
    const Eigen::Matrix3Xf positions = positionsFromCloud(cloud);
    if (positions.cols() != vertices)
      fail(lineName(*open) + ": a state of " + std::to_string(positions.cols()) + " points for a display surface of " +
           std::to_string(vertices) + " vertices");
    if (!positions.allFinite()) fail(lineName(*open) + ": a non-finite state");
    if (!commandFrame.empty() && cloud.header.frame_id != commandFrame)
      fail(lineName(*open) + ": a state in frame '" + cloud.header.frame_id + "', the commands in '" + commandFrame + "'");
    last = positions.cast<double>();
  }
};

}  // namespace

CoarseBagWriter::CoarseBagWriter(const std::string& path, const std::vector<acquisition::PlanEntry>& plan,
                                 const std::string& simulator)
    : bag_(std::make_unique<rosbag::Bag>()) {
  const bool resume = std::filesystem::exists(path);
  if (resume) {
    const acquisition::RecordedCoarse previous = readCoarseBag(path, -1);
    if (planText(previous.plan) != planText(plan))
      throw InvalidInputError(path + ": the recording there was driven by another plan (move it away or give its plan)");
    for (const auto& entry : previous.settled) completed_.insert(entry.first);
    rosbag::Bag reader(path, rosbag::bagmode::Read);
    last_ = rosbag::View(reader).getEndTime();
  }
  try {
    bag_->open(path, resume ? rosbag::bagmode::Append : rosbag::bagmode::Write);
  } catch (const rosbag::BagException& e) {
    throw IoError(path + ": cannot open the recording: " + e.what());
  }
  if (resume) return;
  last_ = ros::Time::now();
  std_msgs::String text;
  text.data = planText(plan);
  bag_->write(kPlanTopic, last_, text);
  text.data = simulator;
  bag_->write(kSimulatorTopic, last_, text);
}

CoarseBagWriter::~CoarseBagWriter() = default;

void CoarseBagWriter::write(std::size_t planLine, const std::vector<SettledStep>& steps) {
  if (steps.empty()) throw InvalidInputError("coarse bag: plan line " + std::to_string(planLine + 1) + " has no settled step");
  // Bag times strictly increase, so a reader sees the messages in the order written (equal times may swap).
  const auto put = [this](const char* topic, const ros::Time& wanted, const auto& message) {
    last_ = std::max(wanted, last_ + ros::Duration(0, 1));
    bag_->write(topic, last_, message);
  };
  std_msgs::String text;
  text.data = "begin " + std::to_string(planLine);
  put(kInteractionTopic, steps.front().command.header.stamp, text);
  for (const SettledStep& step : steps) {
    put(kCommandTopic, step.command.header.stamp, step.command);
    put(kStateTopic, step.state.header.stamp, step.state);
  }
  text.data = "end " + std::to_string(planLine);
  put(kInteractionTopic, last_, text);
  completed_.insert(planLine);
}

acquisition::RecordedCoarse readCoarseBag(const std::string& path, long displayVertices) {
  rosbag::Bag bag;
  try {
    bag.open(path, rosbag::bagmode::Read);
  } catch (const rosbag::BagException& e) {
    throw IoError(path + ": cannot read the recording: " + e.what());
  }
  rosbag::View view(bag);
  for (const rosbag::ConnectionInfo* c : view.getConnections()) {
    const auto expected = expectedTypes().find(c->topic);
    if (expected != expectedTypes().end() && expected->second != c->datatype)
      throw InvalidInputError(path + ": topic " + c->topic + " holds " + c->datatype + ", expected " + expected->second);
  }
  Walk walk{path, displayVertices, {}, {}, {}, {}, {}};
  walk.recorded.path = path;
  // The plan and the simulator first, whatever their time stamps; then the interactions in time order.
  for (const rosbag::MessageInstance& m : rosbag::View(bag, rosbag::TopicQuery(std::vector<std::string>{kPlanTopic, kSimulatorTopic}))) {
    const std::string text = m.instantiate<std_msgs::String>()->data;
    if (m.getTopic() == kSimulatorTopic) {
      walk.recorded.simulator = text;
      continue;
    }
    std::istringstream in(text);
    try {
      walk.recorded.plan = acquisition::readPlan(in, path + " " + kPlanTopic);
    } catch (const IoError& e) {
      walk.fail(std::string("its plan does not parse: ") + e.what());
    }
  }
  if (walk.recorded.plan.empty()) walk.fail(std::string("no plan on ") + kPlanTopic + ": not a recording of acquisition_driver");
  for (const rosbag::MessageInstance& m : rosbag::View(bag, rosbag::TopicQuery(std::vector<std::string>{kInteractionTopic, kCommandTopic, kStateTopic}))) {
    const std::string& topic = m.getTopic();
    if (topic == kInteractionTopic) {
      walk.interaction(m.instantiate<std_msgs::String>()->data);
    } else if (topic == kCommandTopic) {
      walk.commandFrame = m.instantiate<geometry_msgs::PoseStamped>()->header.frame_id;
    } else if (walk.open) {
      walk.state(*m.instantiate<sensor_msgs::PointCloud2>());
    }
  }
  if (walk.open) walk.fail(walk.lineName(*walk.open) + " was begun and not ended (the recording was cut short)");
  if (walk.recorded.settled.empty() && displayVertices >= 0) walk.fail("no complete interaction");
  return walk.recorded;
}

namespace {

bool endsWith(const std::string& text, const std::string& suffix) {
  return text.size() >= suffix.size() && text.compare(text.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// The bag-time window [end, next) of each plan line whose end command is found: the last state in it settled.
std::map<std::size_t, std::pair<ros::Time, ros::Time>> sessionWindows(rosbag::Bag& bag, const std::vector<Eigen::Vector3d>& finals,
                                                                       double tolerance, std::string& frame) {
  std::vector<std::pair<ros::Time, Eigen::Vector3d>> commands;
  for (const rosbag::MessageInstance& m : rosbag::View(bag)) {
    if (!endsWith(m.getTopic(), "servo_cp")) continue;
    const auto pose = m.instantiate<geometry_msgs::PoseStamped>();
    commands.emplace_back(m.getTime(), Eigen::Vector3d(pose->pose.position.x, pose->pose.position.y, pose->pose.position.z));
    frame = pose->header.frame_id;
  }
  std::map<std::size_t, std::pair<ros::Time, ros::Time>> windows;
  std::size_t cursor = 0;
  for (std::size_t line = 0; line < finals.size(); ++line) {
    std::size_t end = cursor;
    while (end < commands.size() && (commands[end].second - finals[line]).norm() > tolerance) ++end;
    if (end == commands.size()) continue;  // not found: the next line is looked for from the same place
    std::size_t away = end + 1;
    while (away < commands.size() && (commands[away].second - finals[line]).norm() <= tolerance) ++away;
    windows[line] = {commands[end].first, away < commands.size() ? commands[away].first : ros::TIME_MAX};
    cursor = away;
  }
  return windows;
}

}  // namespace

acquisition::RecordedCoarse readSessionBag(const std::string& path, long displayVertices, const std::vector<acquisition::PlanEntry>& plan,
                                           const std::vector<Eigen::Vector3d>& finalCentres, double tolerance) {
  if (finalCentres.size() != plan.size())
    throw InvalidInputError("readSessionBag: " + std::to_string(finalCentres.size()) + " final centres for " + std::to_string(plan.size()) +
                            " plan lines");
  rosbag::Bag bag;
  try {
    bag.open(path, rosbag::bagmode::Read);
  } catch (const rosbag::BagException& e) {
    throw IoError(path + ": cannot read the recording: " + e.what());
  }
  for (const rosbag::ConnectionInfo* c : rosbag::View(bag).getConnections()) {
    const bool command = endsWith(c->topic, "servo_cp"), state = endsWith(c->topic, "mesh_state");
    if ((command && c->datatype != "geometry_msgs/PoseStamped") || (state && c->datatype != "sensor_msgs/PointCloud2"))
      throw InvalidInputError(path + ": topic " + c->topic + " holds " + c->datatype + ", expected " +
                              (command ? "geometry_msgs/PoseStamped" : "sensor_msgs/PointCloud2"));
  }
  Walk walk{path, displayVertices, {}, {}, {}, {}, {}};
  walk.recorded.path = path;
  walk.recorded.plan = plan;
  const auto windows = sessionWindows(bag, finalCentres, tolerance, walk.commandFrame);
  for (const rosbag::MessageInstance& m : rosbag::View(bag)) {
    if (!endsWith(m.getTopic(), "mesh_state")) continue;
    for (const auto& [line, window] : windows) {
      if (m.getTime() < window.first || m.getTime() >= window.second) continue;
      walk.open = line;
      walk.state(*m.instantiate<sensor_msgs::PointCloud2>());
      walk.recorded.settled[line] = *walk.last;
      if (walk.recorded.simulator.empty()) walk.recorded.simulator = m.getCallerId();
    }
  }
  if (walk.recorded.settled.empty())
    walk.fail("no interaction of the plan found: no servo_cp command reaches a final tool centre of the plan within " +
              std::to_string(tolerance) + " m, or no mesh_state follows one");
  return walk.recorded;
}

acquisition::RecordedCoarse readSessionBag(const std::string& path, const acquisition::SceneAcquisition& scene,
                                           const std::vector<acquisition::PlanEntry>& plan) {
  std::vector<Eigen::Vector3d> finals;
  for (const acquisition::PlanEntry& entry : plan) finals.push_back(scene.toolCentres(entry).back());
  return readSessionBag(path, scene.fineSurface().numVertices(), plan, finals, 0.05 * scene.scene().tool.radius);
}

}  // namespace deformation_enrichment::ros_layer
