// Built-in demo scene: the slab of the default example set (0.10 x 0.10 x 0.02 m, 1 mm stiff skin, bottom
// fixed) played by its coarse Stable Neo-Hookean simulation. A scripted tool indents and drags at the
// held-out contacts of de_evaluate (interactions that are not in the example set), holds, and lifts off.
// At start-up the coarse quasi-static path of every tap is solved once (a few seconds); the node then plays
// it at `rate`, interpolating between solved steps, and publishes the latched rest mesh (the fine display
// surface the examples were acquired on), the coarse states carried onto it, and the tool's contacts.
#include <ros/ros.h>

#include <algorithm>
#include <cmath>

#include "deformation_enrichment/ToolContactArray.h"
#include "deformation_enrichment/acquisition/example_generation.hpp"
#include "deformation_enrichment/examples/example_set_io.hpp"
#include "deformation_enrichment/ros/conversions.hpp"
#include "deformation_enrichment/scenes/tool_loading.hpp"

namespace de = deformation_enrichment;

namespace {

struct Tap {
  de::acquisition::PlanEntry entry;
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

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "demo_scene");
  ros::NodeHandle nh, pnh("~");
  const std::string frame = pnh.param<std::string>("frame_id", "slab");
  const double rate = pnh.param("rate", 30.0);
  const double period = pnh.param("tap_period", 3.0);
  const int indentSteps = pnh.param("indent_steps", 6), dragSteps = pnh.param("drag_steps", 6);
  const std::string setPath = pnh.param<std::string>("example_set", "");
  if (!(rate > 0.0) || !std::isfinite(rate) || !(period > 0.0) || !std::isfinite(period)) {
    ROS_FATAL("demo slab: ~rate (%g) and ~tap_period (%g) must be positive and finite", rate, period);
    return 1;
  }

  de::acquisition::SlabAcquisitionOptions options;
  std::vector<Tap> taps;
  std::unique_ptr<de::acquisition::SlabAcquisition> slab;
  try {
    // The slab the example set was acquired on (resolutions, materials, tool), so the states match its examples.
    if (!setPath.empty())
      de::acquisition::applyResolutionMetadata(de::examples::loadExampleSet(setPath), options);
    slab = std::make_unique<de::acquisition::SlabAcquisition>(options);
    for (const de::acquisition::PlanEntry& entry : de::acquisition::heldOutSlabContacts()) {
      Tap tap{entry, {}, {}};
      std::string message;
      tap.path = slab->coarsePath(entry, indentSteps, dragSteps, &message);
      if (!message.empty()) ROS_WARN("demo slab: coarse solver: %s", message.c_str());
      const int drag = static_cast<int>(tap.path.size()) - 1 - indentSteps;
      for (int step = 0; step < static_cast<int>(tap.path.size()); ++step)
        tap.tool.push_back(de::scenes::toolDisplacement(step, indentSteps, drag, -Eigen::Vector3d::UnitZ(), entry.depth,
                                                        drag > 0 ? Eigen::Vector3d(entry.drag.normalized()) : Eigen::Vector3d::UnitX(),
                                                        entry.drag.norm()));
      taps.push_back(std::move(tap));
    }
  } catch (const std::exception& e) {
    ROS_FATAL("demo slab: %s", e.what());
    return 1;
  }
  const de::mesh::TriangleMesh& rest = slab->fineSurface();

  std_msgs::Header header;
  header.frame_id = frame;
  header.stamp = ros::Time::now();
  ros::Publisher restPub = nh.advertise<pcl_msgs::PolygonMesh>("rest_mesh", 1, /*latch=*/true);
  ros::Publisher statePub = nh.advertise<sensor_msgs::PointCloud2>("mesh_state", 2);
  ros::Publisher contactsPub = nh.advertise<de::ToolContactArray>("contacts", 2);
  restPub.publish(de::ros_layer::messageFromTriangleMesh(rest, header));
  ROS_INFO("demo slab: %ld surface vertices; coarse SNH paths of %zu taps solved; one tap every %.1f s",
           static_cast<long>(rest.numVertices()), taps.size(), period);

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
      const Eigen::Vector3d tip = tap.entry.point + (1.0 - f) * tap.tool[static_cast<std::size_t>(k)] + f * tap.tool[static_cast<std::size_t>(k + 1)];
      de::ToolContact contact;
      contact.header = header;
      contact.tool_id = "demo_tool";
      contact.in_contact = true;
      contact.position.x = tip.x();
      contact.position.y = tip.y();
      contact.position.z = tip.z();
      contact.normal.z = 1.0;
      contacts.contacts.push_back(contact);
    }
    contactsPub.publish(contacts);
    statePub.publish(de::ros_layer::cloudFromPositions(positions.cast<float>(), header));
    ros::spinOnce();
    loop.sleep();
  }
  return 0;
}
