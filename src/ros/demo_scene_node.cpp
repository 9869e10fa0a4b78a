// Demo scene: a scene file (default: the slab of the default example set, 0.10 x 0.10 x 0.02 m, 1 mm stiff
// skin, bottom fixed) touched by a scripted tool that indents and drags at held-out contacts
// (~contacts_file, or random ones on the touchable surface), holds, and lifts off; it publishes the tool's
// contacts and its frame (~frame_id, default slab) as a static tf child of ~parent_frame (default world;
// empty: no tf). The coarse states (~coarse):
// - snh (default): the scene's coarse Stable Neo-Hookean simulation. At start-up the coarse quasi-static path
//   of every tap is solved once (a few seconds); the node then plays it at `rate`, interpolating between
//   solved steps, and publishes the latched rest mesh (the display surface the examples were acquired on)
//   and the coarse states carried onto it; with ~fine_truth (default true) it also solves the fine path of
//   every tap, on a thread of its own while the coarse ones play (about 2 s per slab tap), and from then on
//   publishes it on fine_state with the stamps of the coarse states: the truth the enrichment node draws
//   beside its output (~marker_fine_offset);
// - simulator: a coarse simulator running beside it (docs/coarse_simulator.md, e.g. bullet_coarse_sim_node)
//   publishes the states and the rest mesh; this node commands its tool on servo_cp, and with ~fine_truth
//   publishes the fine state of each command (solved as for snh) with the command's stamp: the simulator
//   stamps its own states, and the enrichment node draws the newest truth at or before a state's stamp.
#include <geometry_msgs/PoseStamped.h>
#include <ros/ros.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <tf2_ros/static_transform_broadcaster.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <memory>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <thread>

#include "deformation_enrichment/ToolContactArray.h"
#include "deformation_enrichment/acquisition/plan_generation.hpp"
#include "deformation_enrichment/acquisition/scene_acquisition.hpp"
#include "deformation_enrichment/examples/example_set_io.hpp"
#include "deformation_enrichment/ros/conversions.hpp"
#include "deformation_enrichment/acquisition/tool_loading.hpp"
#include "deformation_enrichment/ros/parameter.hpp"

namespace de = deformation_enrichment;
using de::ros_layer::requiredTypeParameter;

namespace {

struct Tap {
  de::acquisition::ToolPath toolPath;
  std::vector<Eigen::Matrix3Xd> path;  // rest, then after each indent and drag step
  std::vector<Eigen::Vector3d> tool;   // tool displacement at each path state
};

// Where in a tap's path the tool is at `phase` in [0, 1) of the period: along the path (0-60 %), holding
// (60-75 %), lifting back along the path (75-90 %), resting (90-100 %). Returns a path parameter in
// [0, steps] (fractional between solved steps).
double pathParameter(double phase, int steps) {
  if (phase < 0.6) return steps * phase / 0.6;
  if (phase < 0.75) return steps;
  if (phase < 0.9) return steps * (0.9 - phase) / 0.15;
  return 0.0;
}

de::ToolContact toolContact(const std_msgs::Header& header, const Eigen::Vector3d& tip, const Eigen::Vector3d& inward) {
  de::ToolContact contact;
  contact.header = header;
  contact.tool_id = "demo_tool";
  contact.in_contact = true;
  contact.position.x = tip.x();
  contact.position.y = tip.y();
  contact.position.z = tip.z();
  contact.normal.x = -inward.x();
  contact.normal.y = -inward.y();
  contact.normal.z = -inward.z();
  return contact;
}

// The coarse quasi-static path of one interaction and the tool's displacement at each of its states.
Tap solveTap(const de::acquisition::SceneAcquisition& scene, const de::acquisition::PlanEntry& entry, int indentSteps,
             int dragSteps) {
  Tap tap{scene.toolPath(entry), {}, {}};
  std::string message;
  tap.path = scene.surfacePath(de::acquisition::SceneAcquisition::Resolution::Coarse, entry, indentSteps, dragSteps, &message);
  if (!message.empty()) ROS_WARN("demo scene: coarse solver: %s", message.c_str());
  const de::acquisition::ToolPath& p = tap.toolPath;
  const int drag = static_cast<int>(tap.path.size()) - 1 - indentSteps;
  const Eigen::Vector3d dragDirection = drag > 0 ? Eigen::Vector3d(p.drag.normalized()) : Eigen::Vector3d::UnitX();
  for (int step = 0; step < static_cast<int>(tap.path.size()); ++step)
    tap.tool.push_back(de::acquisition::toolDisplacement(step, indentSteps, drag, p.inward, p.depth, dragDirection, p.drag.norm()));
  return tap;
}

// The fine paths of the taps (the same steps as the coarse ones), solved one tap after the other on a thread
// of their own; each is available once solved.
class FineTruth {
public:
  FineTruth(const de::acquisition::SceneAcquisition& scene, std::vector<de::acquisition::PlanEntry> entries, int indentSteps,
            int dragSteps)
      : paths_(entries.size()) {
    worker_ = std::thread([this, &scene, entries = std::move(entries), indentSteps, dragSteps] {
      // Lowest priority (the solver's OpenMP threads, started here, inherit it): the states must keep their rate.
      setpriority(PRIO_PROCESS, static_cast<id_t>(syscall(SYS_gettid)), 19);
      try {
        for (std::size_t tap = 0; tap < entries.size() && !stop_; ++tap) {
          std::string message;
          auto path = scene.surfacePath(de::acquisition::SceneAcquisition::Resolution::Fine, entries[tap], indentSteps, dragSteps, &message);
          if (!message.empty()) ROS_WARN("demo scene: fine solver, tap %zu: %s", tap, message.c_str());
          std::lock_guard<std::mutex> lock(mutex_);
          paths_[tap] = std::make_shared<const std::vector<Eigen::Matrix3Xd>>(std::move(path));
        }
        if (!stop_) ROS_INFO("demo scene: the fine truth of every tap is solved");
      } catch (const std::exception& e) {
        ROS_ERROR("demo scene: no fine truth for the taps not yet solved: %s", e.what());
      }
    });
  }
  ~FineTruth() {
    stop_ = true;  // after the tap being solved
    worker_.join();
  }
  /// The fine path of `tap`, null until solved.
  std::shared_ptr<const std::vector<Eigen::Matrix3Xd>> path(std::size_t tap) const {
    std::lock_guard<std::mutex> lock(mutex_);
    return paths_[tap];
  }

private:
  mutable std::mutex mutex_;
  std::vector<std::shared_ptr<const std::vector<Eigen::Matrix3Xd>>> paths_;
  std::atomic<bool> stop_{false};
  std::thread worker_;
};

// Taps and their phases keep time with the clock, not with the node's start, so that whoever knows the period
// knows where in a tap the tool is (scripts/demo takes its screenshot mid-press): tap number + phase.
double tapClock(const ros::Time& now, double period) { return now.toSec() / period; }

// A path's state at solved step k + f (f in [0, 1]).
template <typename State>
State between(const std::vector<State>& path, int k, double f) {
  return (1.0 - f) * path[static_cast<std::size_t>(k)] + f * path[static_cast<std::size_t>(k + 1)];
}

// The scene's frame as an identity child of `parent` in tf: without any tf data for it rviz reports its
// fixed frame missing (Global Status: Warn), although every message is in that frame.
geometry_msgs::TransformStamped frameTransform(const std::string& parent, const std_msgs::Header& header) {
  geometry_msgs::TransformStamped transform;
  transform.header.stamp = header.stamp;
  transform.header.frame_id = parent;
  transform.child_frame_id = header.frame_id;
  transform.transform.rotation.w = 1.0;
  return transform;
}

struct DemoOptions {
  std::string frame, parentFrame, setPath, sceneName, contactsFile, coarse;
  double rate = 30.0, period = 3.0;
  int indentSteps = 6, dragSteps = 6, seed = 7;
  bool fineTruth = true;
};

DemoOptions readSettings(ros::NodeHandle& pnh) {
  DemoOptions s;
  s.frame = requiredTypeParameter<std::string>(pnh, "frame_id", "slab");
  s.parentFrame = requiredTypeParameter<std::string>(pnh, "parent_frame", "world");
  s.rate = requiredTypeParameter(pnh, "rate", s.rate);
  s.period = requiredTypeParameter(pnh, "tap_period", s.period);
  s.indentSteps = requiredTypeParameter(pnh, "indent_steps", s.indentSteps);
  s.dragSteps = requiredTypeParameter(pnh, "drag_steps", s.dragSteps);
  s.setPath = requiredTypeParameter<std::string>(pnh, "example_set", "");
  s.sceneName = requiredTypeParameter<std::string>(pnh, "scene", "slab");
  s.contactsFile = requiredTypeParameter<std::string>(pnh, "contacts_file", "");
  s.seed = requiredTypeParameter(pnh, "seed", s.seed);
  s.coarse = requiredTypeParameter<std::string>(pnh, "coarse", "snh");
  s.fineTruth = requiredTypeParameter(pnh, "fine_truth", s.fineTruth);
  if (!(s.rate > 0.0) || !std::isfinite(s.rate) || !(s.period > 0.0) || !std::isfinite(s.period))
    throw std::runtime_error("~rate (" + std::to_string(s.rate) + ") and ~tap_period (" + std::to_string(s.period) +
                             ") must be positive and finite");
  if (s.coarse != "snh" && s.coarse != "simulator")
    throw std::runtime_error("~coarse must be snh or simulator, got '" + s.coarse + "'");
  return s;
}

// The scene, as the example set recorded it for a procedural scene (resolutions, materials, tool), so the
// states match its examples; scenes with mesh files are taken from their file.
std::unique_ptr<de::acquisition::SceneAcquisition> loadScene(const DemoOptions& s) {
  de::scene_file::SceneDescription description = de::scene_file::readSceneFile(de::scene_file::findSceneFile(s.sceneName));
  if (!s.setPath.empty()) {
    const auto provenance = de::examples::loadExampleSet(s.setPath).metadata.provenance;
    if (provenance && provenance->scene.procedural && description.procedural && provenance->scene.name == description.name)
      description = provenance->scene;
  }
  return std::make_unique<de::acquisition::SceneAcquisition>(description);
}

// Plays the coarse SNH paths of the taps: the rest mesh, the states and the tool's contacts, and the fine
// truth of the taps already solved (`fine`: null for none).
void playSolvedTaps(ros::NodeHandle& nh, const de::acquisition::SceneAcquisition& scene, const std::vector<Tap>& taps,
                    const FineTruth* fine, const DemoOptions& settings, std_msgs::Header header) {
  ros::Publisher restPub = nh.advertise<pcl_msgs::PolygonMesh>("rest_mesh", 1, /*latch=*/true);
  ros::Publisher statePub = nh.advertise<sensor_msgs::PointCloud2>("mesh_state", 2);
  ros::Publisher contactsPub = nh.advertise<de::ToolContactArray>("contacts", 2);
  ros::Publisher finePub;
  if (fine) finePub = nh.advertise<sensor_msgs::PointCloud2>("fine_state", 2);
  restPub.publish(de::ros_layer::messageFromTriangleMesh(scene.fineSurface(), header));
  ros::Rate loop(settings.rate);
  while (ros::ok()) {
    header.stamp = ros::Time::now();
    const double t = tapClock(header.stamp, settings.period);
    const std::size_t index = static_cast<std::size_t>(t) % taps.size();
    const Tap& tap = taps[index];
    const int steps = static_cast<int>(tap.path.size()) - 1;
    const double s = pathParameter(t - std::floor(t), steps);
    const int k = std::min(static_cast<int>(s), steps - 1);
    const double f = s - k;
    const Eigen::Matrix3Xd positions = between(tap.path, k, f);
    de::ToolContactArray contacts;
    contacts.header = header;
    if (s > 0.0) {
      // The tool tip: where the tool has moved the surface point it touches.
      const Eigen::Vector3d tip = tap.toolPath.contact + between(tap.tool, k, f);
      contacts.contacts.push_back(toolContact(header, tip, tap.toolPath.inward));
    }
    contactsPub.publish(contacts);
    // The truth first: the enrichment node draws the fine state of the stamp it has just enriched.
    if (const auto finePath = fine ? fine->path(index) : nullptr)
      finePub.publish(de::ros_layer::cloudFromPositions(between(*finePath, k, f).cast<float>(), header));
    statePub.publish(de::ros_layer::cloudFromPositions(positions.cast<float>(), header));
    ros::spinOnce();
    loop.sleep();
  }
}

// Scripts the tool of a coarse simulator that runs on its own (docs/coarse_simulator.md; e.g.
// bullet_coarse_sim_node, which publishes the states and the rest mesh): the tool sphere's centre on
// servo_cp along each tap's path, lifted clear between taps, and the contact at the sphere's tip where
// measured_cp says the tool is (the simulator may still be moving it towards the command); the fine truth of
// each command once its tap is solved (`fine`: null for none).
void scriptSimulatorTool(ros::NodeHandle& nh, const de::acquisition::SceneAcquisition& scene,
                         const std::vector<de::acquisition::PlanEntry>& entries, const FineTruth* fine,
                         const DemoOptions& settings, std_msgs::Header header) {
  const double radius = scene.scene().tool.radius;
  std::vector<std::vector<Eigen::Vector3d>> centres;
  std::vector<de::acquisition::ToolPath> paths;
  for (const de::acquisition::PlanEntry& entry : entries) {
    centres.push_back(scene.toolCentres(entry));
    paths.push_back(scene.toolPath(entry));
  }
  ros::Publisher commandPub = nh.advertise<geometry_msgs::PoseStamped>("servo_cp", 2);
  ros::Publisher contactsPub = nh.advertise<de::ToolContactArray>("contacts", 2);
  ros::Publisher finePub;
  if (fine) finePub = nh.advertise<sensor_msgs::PointCloud2>("fine_state", 2);
  std::optional<Eigen::Vector3d> measured;
  ros::Subscriber measuredSub = nh.subscribe<geometry_msgs::PoseStamped>("measured_cp", 2, [&](const geometry_msgs::PoseStampedConstPtr& pose) {
    measured = Eigen::Vector3d(pose->pose.position.x, pose->pose.position.y, pose->pose.position.z);
  });
  ros::Rate loop(settings.rate);
  while (ros::ok()) {
    header.stamp = ros::Time::now();
    const double t = tapClock(header.stamp, settings.period);
    const std::size_t tap = static_cast<std::size_t>(t) % centres.size();
    const std::vector<Eigen::Vector3d>& c = centres[tap];
    const de::acquisition::ToolPath& path = paths[tap];
    const int steps = static_cast<int>(c.size()) - 1;
    const double s = pathParameter(t - std::floor(t), steps);
    const int k = std::min(static_cast<int>(s), steps - 1);
    const double f = s - k;
    const Eigen::Vector3d centre = s > 0.0 ? between(c, k, f)
                                           : Eigen::Vector3d(c.front() - std::max(radius, 2.0 * path.depth) * path.inward);
    if (const auto finePath = fine ? fine->path(tap) : nullptr)
      finePub.publish(de::ros_layer::cloudFromPositions(between(*finePath, k, f).cast<float>(), header));
    commandPub.publish(de::ros_layer::poseAt(centre, header));
    de::ToolContactArray contacts;
    contacts.header = header;
    // Only once the simulator says where its tool is: it publishes that with its states, so the contacts do
    // not reach the enrichment node before any state (where they would be dropped with an error).
    if (s > 0.0 && measured) contacts.contacts.push_back(toolContact(header, *measured + radius * path.inward, path.inward));
    contactsPub.publish(contacts);
    ros::spinOnce();
    loop.sleep();
  }
}

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "demo_scene");
  ros::NodeHandle nh, pnh("~");
  DemoOptions settings;
  std::vector<Tap> taps;
  std::vector<de::acquisition::PlanEntry> entries;
  std::unique_ptr<de::acquisition::SceneAcquisition> scene;
  try {
    settings = readSettings(pnh);
    scene = loadScene(settings);
    entries = settings.contactsFile.empty() ? de::acquisition::randomContacts(*scene, 4, static_cast<unsigned>(settings.seed))
                                            : de::acquisition::readPlan(settings.contactsFile);
    if (settings.coarse == "snh")
      for (const de::acquisition::PlanEntry& entry : entries) taps.push_back(solveTap(*scene, entry, settings.indentSteps, settings.dragSteps));
  } catch (const std::exception& e) {
    ROS_FATAL("demo scene: %s", e.what());
    return 1;
  }
  std_msgs::Header header;
  header.frame_id = settings.frame;
  header.stamp = ros::Time::now();
  tf2_ros::StaticTransformBroadcaster frames;
  if (!settings.parentFrame.empty() && settings.parentFrame != settings.frame)
    frames.sendTransform(frameTransform(settings.parentFrame, header));
  ROS_INFO("demo scene %s: %ld surface vertices; %zu taps, one every %.1f s; coarse states from %s", settings.sceneName.c_str(),
           static_cast<long>(scene->fineSurface().numVertices()), entries.size(), settings.period,
           settings.coarse == "snh" ? "the coarse SNH paths solved at start-up" : "the simulator (servo_cp out, measured_cp in)");
  // The fine paths in the steps of the coarse ones: the demo's own, or those of the simulator's commands.
  const bool own = settings.coarse == "snh";
  const de::scene_file::Solve& solve = scene->scene().solve;
  std::optional<FineTruth> fine;
  if (settings.fineTruth)
    fine.emplace(*scene, entries, own ? settings.indentSteps : solve.indentSteps, own ? settings.dragSteps : solve.dragSteps);
  if (own) playSolvedTaps(nh, *scene, taps, fine ? &*fine : nullptr, settings, header);
  else scriptSimulatorTool(nh, *scene, entries, fine ? &*fine : nullptr, settings, header);
  return 0;
}
