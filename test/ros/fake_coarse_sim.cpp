// A stand-in coarse simulator for acquisition_driver's rostest (docs/coarse_simulator.md's contract, no
// physics): it publishes the scene's display surface on mesh_state at ~rate with every vertex inside the tool
// sphere pushed out to the sphere's surface, takes the sphere's centre on servo_cp and parks the tool on reset.
// It settles at once, so the test exercises the driver and the bag, not a solver.
#include <geometry_msgs/PoseStamped.h>
#include <ros/ros.h>
#include <std_srvs/Empty.h>

#include "deformation_enrichment/ros/conversions.hpp"
#include "deformation_enrichment/scenes/scene_models.hpp"

namespace de = deformation_enrichment;

int main(int argc, char** argv) {
  ros::init(argc, argv, "fake_coarse_sim");
  ros::NodeHandle nh, pnh("~");
  const de::scene_file::SceneDescription scene =
      de::scene_file::readSceneFile(de::scene_file::findSceneFile(pnh.param<std::string>("scene", "slab")));
  const de::mesh::TriangleMesh surface = de::scenes::sceneGeometry(scene).surface;
  const double radius = scene.tool.radius;
  const Eigen::Vector3d parked(0.0, 0.0, 1.0);
  Eigen::Vector3d tool = parked;
  std_msgs::Header header;
  header.frame_id = pnh.param<std::string>("frame_id", "slab");
  ros::Publisher rest = nh.advertise<pcl_msgs::PolygonMesh>("rest_mesh", 1, true);
  rest.publish(de::ros_layer::messageFromTriangleMesh(surface, header));
  ros::Publisher states = nh.advertise<sensor_msgs::PointCloud2>("mesh_state", 10);
  ros::Subscriber commands = nh.subscribe<geometry_msgs::PoseStamped>("servo_cp", 10, [&](const geometry_msgs::PoseStampedConstPtr& p) {
    tool = Eigen::Vector3d(p->pose.position.x, p->pose.position.y, p->pose.position.z);
  });
  ros::ServiceServer reset = nh.advertiseService<std_srvs::Empty::Request, std_srvs::Empty::Response>(
      "reset", [&](std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
        tool = parked;
        return true;
      });
  ros::Rate loop(pnh.param("rate", 100.0));
  while (ros::ok()) {
    ros::spinOnce();
    Eigen::Matrix3Xd x = surface.vertices;
    for (Eigen::Index v = 0; v < x.cols(); ++v) {
      const Eigen::Vector3d out = x.col(v) - tool;
      if (out.norm() < radius) x.col(v) = tool + radius * out.normalized();
    }
    header.stamp = ros::Time::now();
    states.publish(de::ros_layer::cloudFromPositions(x.cast<float>(), header));
    loop.sleep();
  }
  return 0;
}
