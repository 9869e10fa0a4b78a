#pragma once
// A recording of a coarse simulator driven through an acquisition plan (docs/coarse_simulator.md), as
// acquisition_driver writes it and de_make_examples / de_evaluate --coarse-bag read it. Topics:
//   /acquisition/plan         std_msgs/String, once: the plan CSV (x,y,z,depth,dx,dy,dz per line)
//   /acquisition/simulator    std_msgs/String, once: the simulator as it announced itself
//   /acquisition/interaction  std_msgs/String: "begin <line>" and "end <line>" (0-based plan line) around
//   /servo_cp                 geometry_msgs/PoseStamped: each commanded tool centre, and
//   /mesh_state               sensor_msgs/PointCloud2: the state the simulator settled in after it.
// An interaction is written whole, once it has settled at every step, so a recording cut short holds only
// complete interactions; its coarse half is the last state before its "end".
#include <cstddef>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include <geometry_msgs/PoseStamped.h>
#include <sensor_msgs/PointCloud2.h>

#include "deformation_enrichment/acquisition/recorded_coarse.hpp"
#include "deformation_enrichment/acquisition/scene_acquisition.hpp"

namespace rosbag {
class Bag;
}

namespace deformation_enrichment::ros_layer {

inline constexpr const char* kPlanTopic = "/acquisition/plan";
inline constexpr const char* kSimulatorTopic = "/acquisition/simulator";
inline constexpr const char* kInteractionTopic = "/acquisition/interaction";
inline constexpr const char* kCommandTopic = "/servo_cp";
inline constexpr const char* kStateTopic = "/mesh_state";

/// One step of an interaction: the command and the state the simulator settled in.
struct SettledStep {
  geometry_msgs::PoseStamped command;
  sensor_msgs::PointCloud2 state;
};

/// Writes a recording. A new file gets the plan and the simulator first; an existing one (a resumed run) is
/// appended to after its plan is checked against `plan`. Throws IoError naming the file when it cannot be
/// opened or read, InvalidInputError when an existing recording was driven by another plan.
class CoarseBagWriter {
public:
  CoarseBagWriter(const std::string& path, const std::vector<acquisition::PlanEntry>& plan, const std::string& simulator);
  ~CoarseBagWriter();
  /// Plan lines already complete in the file (a resumed run skips them).
  const std::set<std::size_t>& completed() const { return completed_; }
  /// Appends one whole interaction.
  void write(std::size_t planLine, const std::vector<SettledStep>& steps);

private:
  std::unique_ptr<rosbag::Bag> bag_;
  std::set<std::size_t> completed_;
  ros::Time last_;  ///< the bag time of the last message written
};

/// Reads a recording for a display surface of `displayVertices` vertices. Throws IoError naming the file
/// for an unreadable bag, InvalidInputError naming the problem for: a topic of the wrong message type, no
/// plan or a plan that does not parse, a state whose point count is not `displayVertices` (both counts
/// named), non-finite states (the plan line named), states in another frame than the commands, an
/// interaction begun and not ended or ended without a state, a line beyond the plan, or no interaction.
/// With `displayVertices` < 0 only the plan, the simulator and which lines are complete are read (empty states).
acquisition::RecordedCoarse readCoarseBag(const std::string& path, long displayVertices);

/// A session recorded with the user's own tools (`rosbag record servo_cp mesh_state`, no driver; topics are
/// matched by the end of their names) whose interactions are `plan`, in order. Interaction i ends at the
/// first command after interaction i-1's end within `tolerance` of `finalCentres[i]` (its path's last tool
/// centre, SceneAcquisition::toolCentres); its settled state is the last state before the next command
/// that moves the tool away from there, or before the bag's end. An interaction whose end is not found has
/// no state. The simulator is the publisher of the states. Throws as readCoarseBag for an unreadable bag,
/// wrong types, point counts or frames and non-finite states, and when no interaction is found.
acquisition::RecordedCoarse readSessionBag(const std::string& path, long displayVertices, const std::vector<acquisition::PlanEntry>& plan,
                                           const std::vector<Eigen::Vector3d>& finalCentres, double tolerance);

/// readSessionBag on `scene`'s display surface, each plan line's last tool centre on it, and a tolerance of
/// 5 % of its tool radius.
acquisition::RecordedCoarse readSessionBag(const std::string& path, const acquisition::SceneAcquisition& scene,
                                           const std::vector<acquisition::PlanEntry>& plan);

}  // namespace deformation_enrichment::ros_layer
