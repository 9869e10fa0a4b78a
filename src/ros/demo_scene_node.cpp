// Demo scene: a scene file (default: the slab of the default example set, 0.10 x 0.10 x 0.02 m, 1 mm stiff
// skin, bottom fixed) played by its coarse Stable Neo-Hookean simulation. A scripted tool indents and drags
// at held-out contacts (~contacts_file, or random ones on the touchable surface), holds, and lifts off.
// At start-up the coarse quasi-static path of every tap is solved once (a few seconds); the node then plays
// it at `rate`, interpolating between solved steps, and publishes the latched rest mesh (the display surface
// the examples were acquired on), the coarse states carried onto it, the tool's contacts, and its frame
// (~frame_id, default slab) as a static tf child of ~parent_frame (default world; empty: no tf).
#include <ros/ros.h>
#include <tf2_ros/static_transform_broadcaster.h>

#include <algorithm>
#include <cmath>

#include "deformation_enrichment/ToolContactArray.h"
#include "deformation_enrichment/acquisition/plan_generation.hpp"
#include "deformation_enrichment/acquisition/scene_acquisition.hpp"
#include "deformation_enrichment/examples/example_set_io.hpp"
#include "deformation_enrichment/ros/conversions.hpp"
#include "deformation_enrichment/acquisition/tool_loading.hpp"

namespace de = deformation_enrichment;

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
  tap.path = scene.coarsePath(entry, indentSteps, dragSteps, &message);
  if (!message.empty()) ROS_WARN("demo scene: coarse solver: %s", message.c_str());
  const de::acquisition::ToolPath& p = tap.toolPath;
  const int drag = static_cast<int>(tap.path.size()) - 1 - indentSteps;
  const Eigen::Vector3d dragDirection = drag > 0 ? Eigen::Vector3d(p.drag.normalized()) : Eigen::Vector3d::UnitX();
  for (int step = 0; step < static_cast<int>(tap.path.size()); ++step)
    tap.tool.push_back(de::acquisition::toolDisplacement(step, indentSteps, drag, p.inward, p.depth, dragDirection, p.drag.norm()));
  return tap;
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

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "demo_scene");
  ros::NodeHandle nh, pnh("~");
  const std::string frame = pnh.param<std::string>("frame_id", "slab");
  const std::string parentFrame = pnh.param<std::string>("parent_frame", "world");
  const double rate = pnh.param("rate", 30.0);
  const double period = pnh.param("tap_period", 3.0);
  const int indentSteps = pnh.param("indent_steps", 6), dragSteps = pnh.param("drag_steps", 6);
  const std::string setPath = pnh.param<std::string>("example_set", "");
  const std::string sceneName = pnh.param<std::string>("scene", "slab");
  const std::string contactsFile = pnh.param<std::string>("contacts_file", "");
  const int seed = pnh.param("seed", 7);
  if (!(rate > 0.0) || !std::isfinite(rate) || !(period > 0.0) || !std::isfinite(period)) {
    ROS_FATAL("demo scene: ~rate (%g) and ~tap_period (%g) must be positive and finite", rate, period);
    return 1;
  }

  std::vector<Tap> taps;
  std::unique_ptr<de::acquisition::SceneAcquisition> scene;
  try {
    de::scene_file::SceneDescription description = de::scene_file::readSceneFile(de::scene_file::findSceneFile(sceneName));
    // A procedural scene as the example set recorded it (resolutions, materials, tool), so the states match
    // its examples; scenes with mesh files are taken from their file.
    if (!setPath.empty()) {
      const auto provenance = de::examples::loadExampleSet(setPath).metadata.provenance;
      if (provenance && provenance->scene.procedural && description.procedural && provenance->scene.name == description.name)
        description = provenance->scene;
    }
    scene = std::make_unique<de::acquisition::SceneAcquisition>(description);
    const auto entries = contactsFile.empty() ? de::acquisition::randomContacts(*scene, 4, static_cast<unsigned>(seed))
                                              : de::acquisition::readPlan(contactsFile);
    for (const de::acquisition::PlanEntry& entry : entries) taps.push_back(solveTap(*scene, entry, indentSteps, dragSteps));
  } catch (const std::exception& e) {
    ROS_FATAL("demo scene: %s", e.what());
    return 1;
  }
  const de::mesh::TriangleMesh& rest = scene->fineSurface();

  std_msgs::Header header;
  header.frame_id = frame;
  header.stamp = ros::Time::now();
  ros::Publisher restPub = nh.advertise<pcl_msgs::PolygonMesh>("rest_mesh", 1, /*latch=*/true);
  ros::Publisher statePub = nh.advertise<sensor_msgs::PointCloud2>("mesh_state", 2);
  ros::Publisher contactsPub = nh.advertise<de::ToolContactArray>("contacts", 2);
  restPub.publish(de::ros_layer::messageFromTriangleMesh(rest, header));
  tf2_ros::StaticTransformBroadcaster frames;
  if (!parentFrame.empty() && parentFrame != frame) frames.sendTransform(frameTransform(parentFrame, header));
  ROS_INFO("demo scene %s: %ld surface vertices; coarse SNH paths of %zu taps solved; one tap every %.1f s",
           sceneName.c_str(), static_cast<long>(rest.numVertices()), taps.size(), period);

  const ros::Time start = ros::Time::now();
  ros::Rate loop(rate);
  while (ros::ok()) {
    header.stamp = ros::Time::now();
    const double t = (header.stamp - start).toSec() / period;
    const Tap& tap = taps[static_cast<std::size_t>(t) % taps.size()];
    const int steps = static_cast<int>(tap.path.size()) - 1;
    const double s = pathParameter(t - std::floor(t), steps);
    const int k = std::min(static_cast<int>(s), steps - 1);
    const double f = s - k;
    const Eigen::Matrix3Xd positions = (1.0 - f) * tap.path[static_cast<std::size_t>(k)] + f * tap.path[static_cast<std::size_t>(k + 1)];
    de::ToolContactArray contacts;
    contacts.header = header;
    if (s > 0.0) {
      // The tool tip: where the tool has moved the surface point it touches.
      const Eigen::Vector3d tip = tap.toolPath.contact + (1.0 - f) * tap.tool[static_cast<std::size_t>(k)] + f * tap.tool[static_cast<std::size_t>(k + 1)];
      contacts.contacts.push_back(toolContact(header, tip, tap.toolPath.inward));
    }
    contactsPub.publish(contacts);
    statePub.publish(de::ros_layer::cloudFromPositions(positions.cast<float>(), header));
    ros::spinOnce();
    loop.sleep();
  }
  return 0;
}
