// acquisition_driver: drives the user's own coarse simulator through a scene's acquisition plan over ROS and
// records the states it settles in (docs/coarse_simulator.md), so that examples are made against the coarse
// model that runs live [Seiler14 §3]. For each plan interaction it resets the simulator (`reset`,
// std_srvs/Empty; without one it lifts the tool and waits for the tissue to settle), commands the tool
// sphere's centre on `servo_cp` along the same indent-then-drag path, in the same steps, as the package's
// fine solve, waits at each step until `mesh_state` settles, and appends the whole interaction to ~bag.
// Rerun with the same ~bag, it resumes after the last complete interaction. The plan: ~plan (CSV), the first
// ~examples of the scene's automatic plan, ~held_out random interactions (~seed), or the scene's plan.
#include <ros/ros.h>
#include <std_srvs/Empty.h>

#include <chrono>
#include <cmath>
#include <limits>
#include <optional>

#include "deformation_enrichment/acquisition/plan_generation.hpp"
#include "deformation_enrichment/acquisition/scene_acquisition.hpp"
#include "deformation_enrichment/ros/coarse_bag.hpp"
#include "deformation_enrichment/ros/conversions.hpp"
#include "deformation_enrichment/seconds_since.hpp"
#include "deformation_enrichment/ros/parameter.hpp"

namespace de = deformation_enrichment;
using de::ros_layer::requiredTypeParameter;
using Clock = std::chrono::steady_clock;
constexpr float kInfinity = std::numeric_limits<float>::infinity();

namespace {

struct DriverOptions {
  std::string bag, frame, simulator;
  double settleTolerance = 1e-6, settleTimeout = 10.0;
  int settleStates = 3;
  bool stopOnTimeout = false;
};

// Stops the run: the message is the reason, the bag keeps every complete interaction.
struct Stop : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class Driver {
public:
  Driver(ros::NodeHandle& nh, DriverOptions settings, const de::acquisition::SceneAcquisition& scene)
      : settings_(std::move(settings)), scene_(scene), vertices_(scene.fineSurface().numVertices()) {
    commands_ = nh.advertise<geometry_msgs::PoseStamped>("servo_cp", 10);
    states_ = nh.subscribe("mesh_state", 10, &Driver::onState, this);
    measured_ = nh.subscribe("measured_cp", 10, &Driver::onMeasured, this);
    reset_ = nh.serviceClient<std_srvs::Empty>("reset");
  }

  // Acquires every plan line not yet in the bag. Throws Stop.
  void run(const std::vector<de::acquisition::PlanEntry>& plan) {
    awaitFirstState();
    if (!fault_.empty()) throw Stop(fault_);
    if (settings_.simulator.empty()) settings_.simulator = publisher_;
    if (settings_.frame.empty()) settings_.frame = frame_;
    de::ros_layer::CoarseBagWriter bag(settings_.bag, plan, settings_.simulator);
    const std::size_t todo = plan.size() - bag.completed().size();
    ROS_INFO("acquisition driver: %zu of %zu interactions to record from %s into %s (%zu already there)", todo, plan.size(),
             settings_.simulator.c_str(), settings_.bag.c_str(), bag.completed().size());
    std::size_t done = 0;
    for (std::size_t line = 0; line < plan.size() && ros::ok(); ++line) {
      if (bag.completed().count(line)) continue;
      const auto start = Clock::now();
      overhead_ = 0.0;
      std::vector<de::ros_layer::SettledStep> steps;
      const std::string refused = interaction(line, plan[line], steps);
      ++done;
      if (!refused.empty()) {
        ROS_ERROR("acquisition driver: interaction %zu of %zu (plan line %zu) refused: %s", done, todo, line + 1, refused.c_str());
        continue;
      }
      const auto writeStart = Clock::now();
      bag.write(line, steps);
      overhead_ += de::secondsSince(writeStart);
      const double total = de::secondsSince(start);
      ROS_INFO("acquisition driver: interaction %zu of %zu (plan line %zu): %zu steps in %.2f s, %.0f ms per step, driver %.2f ms per step",
               done, todo, line + 1, steps.size(), total, 1e3 * total / steps.size(), 1e3 * overhead_ / steps.size());
    }
  }

private:

  void onState(const ros::MessageEvent<const sensor_msgs::PointCloud2>& event) {
    const auto start = Clock::now();
    const sensor_msgs::PointCloud2ConstPtr cloud = event.getConstMessage();
    const long points = static_cast<long>(cloud->width) * cloud->height;
    if (points != vertices_) {
      fault_ = "the simulator's mesh_state has " + std::to_string(points) + " points, the scene's display surface " +
               std::to_string(vertices_) + " vertices";
      return;
    }
    // A callback must not throw through roscpp: the waiting loops stop on fault_. The motion is read from the
    // messages themselves, and only until a vertex has moved past the tolerance: a simulator sends hundreds
    // of states a step, nearly all of them still moving. A settled state has been scanned whole: it is finite.
    try {
      const float tolerance = static_cast<float>(settings_.settleTolerance);
      if (latest_) motion_ = de::ros_layer::largestMotion(*cloud, *latest_, tolerance);
      else motion_ = de::ros_layer::positionsFromCloud(*cloud).allFinite() ? kInfinity : std::numeric_limits<float>::quiet_NaN();
    } catch (const std::exception& e) {
      fault_ = std::string("a mesh_state that cannot be read: ") + e.what();
      return;
    }
    nonFinite_ = nonFinite_ || std::isnan(motion_);
    // A simulator that moves its tool towards the command over several states (and says where it is on
    // measured_cp) is not settled while the tool is on its way, however still the tissue.
    quiet_ = motion_ < settings_.settleTolerance && toolArrived() ? quiet_ + 1 : 0;
    previous_ = latest_;
    latest_ = cloud;
    ++received_;
    if (publisher_.empty()) publisher_ = event.getPublisherName(), frame_ = cloud->header.frame_id;
    overhead_ += de::secondsSince(start);
  }

  void onMeasured(const geometry_msgs::PoseStamped& pose) {
    toolAt_ = Eigen::Vector3d(pose.pose.position.x, pose.pose.position.y, pose.pose.position.z);
  }

  bool toolArrived() const { return !toolAt_ || !commanded_ || (*toolAt_ - *commanded_).norm() <= settings_.settleTolerance; }

  // The first state, and the simulator listening on servo_cp: a command published before that connection
  // exists is lost, and its step would time out.
  void awaitFirstState() {
    const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(30.0);
    while (ros::ok() && (received_ == 0 || commands_.getNumSubscribers() == 0)) {
      if (!fault_.empty()) throw Stop(fault_);
      if (ros::WallTime::now() > deadline)
        throw Stop(received_ == 0 ? "no mesh_state from the simulator in 30 s (is it running, and remapped?)"
                                  : "no subscriber to servo_cp in 30 s (is the simulator's command topic remapped?)");
      ros::spinOnce();
      ros::WallDuration(0.001).sleep();
    }
  }

  geometry_msgs::PoseStamped command(const Eigen::Vector3d& centre) const {
    std_msgs::Header header;
    header.stamp = ros::Time::now();
    header.frame_id = settings_.frame;
    return de::ros_layer::poseAt(centre, header);
  }

  // Publishes `pose` and waits until ~settle_states consecutive states each moved less than the tolerance.
  // Returns an empty string, or why the step failed.
  std::string settle(const geometry_msgs::PoseStamped& pose, de::ros_layer::SettledStep* step) {
    commanded_ = Eigen::Vector3d(pose.pose.position.x, pose.pose.position.y, pose.pose.position.z);
    commands_.publish(pose);
    const std::uint64_t first = received_;
    quiet_ = 0;
    nonFinite_ = false;
    const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(settings_.settleTimeout);
    // One state more than the quiet count: the first state after the command may predate it.
    while (ros::ok() && (quiet_ < settings_.settleStates || received_ < first + settings_.settleStates + 1)) {
      if (!fault_.empty()) throw Stop(fault_);
      if (nonFinite_) return "a non-finite state";
      if (ros::WallTime::now() > deadline)
        return "no settle in " + std::to_string(settings_.settleTimeout) + " s (last motion " + std::to_string(lastMotion()) + " m)";
      ros::spinOnce();
      ros::WallDuration(0.0005).sleep();
    }
    if (!ros::ok()) throw Stop("shut down");
    if (step) *step = {pose, *latest_};
    return {};
  }

  // The largest vertex motion between the last two states (infinite before two have arrived).
  float lastMotion() const { return previous_ ? de::ros_layer::largestMotion(*latest_, *previous_, kInfinity) : kInfinity; }

  // Rest before an interaction: the simulator's reset (retried once), or the tool lifted clear and the
  // tissue left to settle.
  void reset(const Eigen::Vector3d& clear) {
    if (!reset_.exists()) {
      if (!warnedNoReset_) ROS_WARN("acquisition driver: no reset service: lifting the tool and waiting for the tissue to settle");
      warnedNoReset_ = true;
      const std::string problem = settle(command(clear), nullptr);
      if (!problem.empty()) throw Stop("lifting the tool to rest the tissue: " + problem);
      return;
    }
    std_srvs::Empty call;
    if (!reset_.call(call) && !reset_.call(call)) throw Stop("the simulator's reset failed twice");
  }

  // Records one plan line into `steps`; returns why it was refused (empty when it was not).
  std::string interaction(std::size_t line, const de::acquisition::PlanEntry& entry, std::vector<de::ros_layer::SettledStep>& steps) {
    const std::vector<Eigen::Vector3d> centres = scene_.toolCentres(entry);
    const de::acquisition::ToolPath path = scene_.toolPath(entry);
    const double radius = scene_.scene().tool.radius;
    reset(centres.front() - std::max(radius, 2.0 * path.depth) * path.inward);  // lifted clear of the contact
    steps.resize(centres.size());
    for (std::size_t step = 0; step < centres.size(); ++step) {
      const std::string problem = settle(command(centres[step]), &steps[step]);
      if (problem.empty()) continue;
      const std::string where = "step " + std::to_string(step) + " of " + std::to_string(centres.size() - 1) + ": " + problem;
      if (problem.rfind("no settle", 0) == 0 && settings_.stopOnTimeout)
        throw Stop("plan line " + std::to_string(line + 1) + ", " + where);
      return where;
    }
    return {};
  }

  DriverOptions settings_;
  const de::acquisition::SceneAcquisition& scene_;
  const long vertices_;
  ros::Publisher commands_;
  ros::Subscriber states_, measured_;
  std::optional<Eigen::Vector3d> toolAt_, commanded_;  // measured_cp (when the simulator publishes it), servo_cp
  ros::ServiceClient reset_;
  sensor_msgs::PointCloud2ConstPtr latest_, previous_;
  std::uint64_t received_ = 0;
  int quiet_ = 0;
  float motion_ = kInfinity;
  bool nonFinite_ = false, warnedNoReset_ = false;
  std::string publisher_, frame_, fault_;
  double overhead_ = 0.0;
};

// ~settle_*, ~on_timeout, ~bag, ~frame_id, ~simulator_name; throws Stop naming a bad value.
DriverOptions readSettings(ros::NodeHandle& pnh) {
  DriverOptions s;
  s.bag = requiredTypeParameter<std::string>(pnh, "bag", "");
  s.frame = requiredTypeParameter<std::string>(pnh, "frame_id", "");
  s.simulator = requiredTypeParameter<std::string>(pnh, "simulator_name", "");
  s.settleTolerance = requiredTypeParameter(pnh, "settle_tolerance", s.settleTolerance);
  s.settleStates = requiredTypeParameter(pnh, "settle_states", s.settleStates);
  s.settleTimeout = requiredTypeParameter(pnh, "settle_timeout", s.settleTimeout);
  const std::string onTimeout = requiredTypeParameter<std::string>(pnh, "on_timeout", "skip");
  if (s.bag.empty()) throw Stop("~bag (the recording to write) is required");
  if (!(s.settleTolerance > 0.0) || !std::isfinite(s.settleTolerance))
    throw Stop("~settle_tolerance must be positive and finite, got " + std::to_string(s.settleTolerance));
  if (s.settleStates < 1) throw Stop("~settle_states must be at least 1, got " + std::to_string(s.settleStates));
  if (!(s.settleTimeout > 0.0) || !std::isfinite(s.settleTimeout))
    throw Stop("~settle_timeout must be positive and finite, got " + std::to_string(s.settleTimeout));
  if (onTimeout != "skip" && onTimeout != "stop") throw Stop("~on_timeout must be skip or stop, got '" + onTimeout + "'");
  s.stopOnTimeout = onTimeout == "stop";
  return s;
}

// rosrun's _name:=value stays on the master after the run. ~plan, ~examples and ~held_out choose what one
// run records, so they are removed when it ends: the next run on the same master (the held-out interactions
// after the examples, say) must not inherit the previous one's choice.
class RunChoiceParameters {
public:
  explicit RunChoiceParameters(const ros::NodeHandle& pnh) : pnh_(pnh) {}
  RunChoiceParameters(const RunChoiceParameters&) = delete;
  RunChoiceParameters& operator=(const RunChoiceParameters&) = delete;
  ~RunChoiceParameters() {
    for (const char* name : {"plan", "examples", "held_out"}) pnh_.deleteParam(name);
  }

private:
  ros::NodeHandle pnh_;
};

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "acquisition_driver");
  ros::NodeHandle nh, pnh("~");
  const RunChoiceParameters runChoice(pnh);
  try {
    const DriverOptions settings = readSettings(pnh);
    de::scene_file::SceneDescription scene = de::scene_file::readSceneFile(de::scene_file::findSceneFile(requiredTypeParameter<std::string>(pnh, "scene", "slab")));
    const std::string planPath = requiredTypeParameter<std::string>(pnh, "plan", "");
    const int examples = requiredTypeParameter(pnh, "examples", 0), heldOut = requiredTypeParameter(pnh, "held_out", 0), seed = requiredTypeParameter(pnh, "seed", 1);
    if (examples < 0 || heldOut < 0)
      throw Stop("~examples and ~held_out must be positive (0: not used), got " + std::to_string(examples) + " and " + std::to_string(heldOut));
    if (!planPath.empty() + (examples > 0) + (heldOut > 0) > 1)
      throw Stop("give one of ~plan, ~examples and ~held_out, got plan '" + planPath + "', examples " + std::to_string(examples) +
                 ", held_out " + std::to_string(heldOut));
    if (!planPath.empty()) scene.plan = planPath;
    else if (examples > 0) scene.plan = "auto";  // the nested plan, as de_make_examples --examples
    ROS_INFO("acquisition driver: scene %s: building its models...", scene.name.c_str());
    de::acquisition::SceneAcquisition acquisition(scene);
    // Held-out interactions are drawn as de_evaluate draws them (seeded, uniform over the touchable surface).
    const auto plan = heldOut > 0 ? de::acquisition::randomContacts(acquisition, heldOut, static_cast<unsigned>(seed))
                                  : de::acquisition::scenePlan(acquisition, examples > 0 ? std::optional<int>(examples) : std::nullopt);
    Driver(nh, settings, acquisition).run(plan);
  } catch (const std::exception& e) {
    ROS_FATAL("acquisition driver: %s", e.what());
    return 1;
  }
  return 0;
}
