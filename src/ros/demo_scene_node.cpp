// Built-in demo scene: a procedurally generated tissue slab (0.10 x 0.10 x 0.02 m, bottom fixed) and a
// scripted tool tapping it at a few points. The coarse state is a smooth analytic dent under the tool,
// standing in for a coarse real-time simulation; it publishes the latched rest mesh, mesh states and contacts.
#include <ros/ros.h>

#include <cmath>

#include "deformation_enrichment/ToolContactArray.h"
#include "deformation_enrichment/mesh/grid_tet_mesh.hpp"
#include "deformation_enrichment/mesh/tet_surface.hpp"
#include "deformation_enrichment/ros/conversions.hpp"

namespace de = deformation_enrichment;

namespace {

struct ToolState {
  Eigen::Vector2d xy;
  double depth;  // indentation [m], 0 when lifted
};

// Taps at the corners of a square around the centre, one tap per period: down and up along a sin^2 profile,
// lifted for the last quarter of each period.
ToolState scriptedTool(double t, double period, double maxDepth) {
  static const Eigen::Vector2d points[4] = {{-0.02, -0.02}, {0.02, -0.02}, {0.02, 0.02}, {-0.02, 0.02}};
  const int tap = static_cast<int>(std::floor(t / period));
  const double phase = t / period - tap;
  const double depth = phase < 0.75 ? maxDepth * std::pow(std::sin(M_PI * phase / 0.75), 2) : 0.0;
  return {points[((tap % 4) + 4) % 4], depth};
}

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "demo_scene");
  ros::NodeHandle nh, pnh("~");
  const std::string frame = pnh.param<std::string>("frame_id", "slab");
  const double rate = pnh.param("rate", 30.0);
  const int cellsXY = pnh.param("cells_xy", 40);
  const int cellsZ = pnh.param("cells_z", 4);
  const double period = pnh.param("tap_period", 2.0);
  const double maxDepth = pnh.param("tap_depth", 0.004);
  const double width = 0.10, thickness = 0.02, dentRadius = 0.008;

  const de::mesh::TetSurface slab = de::mesh::extractSurface(de::mesh::gridTetMesh(
      Eigen::Vector3d(-width / 2, -width / 2, 0.0), Eigen::Vector3d(width / 2, width / 2, thickness),
      Eigen::Vector3i(cellsXY, cellsXY, cellsZ)));
  const de::mesh::TriangleMesh& rest = slab.surface;

  std_msgs::Header header;
  header.frame_id = frame;
  header.stamp = ros::Time::now();
  ros::Publisher restPub = nh.advertise<pcl_msgs::PolygonMesh>("rest_mesh", 1, /*latch=*/true);
  ros::Publisher statePub = nh.advertise<sensor_msgs::PointCloud2>("mesh_state", 2);
  ros::Publisher contactsPub = nh.advertise<de::ToolContactArray>("contacts", 2);
  restPub.publish(de::ros_layer::messageFromTriangleMesh(rest, header));
  ROS_INFO("demo slab: %ld surface vertices, %ld triangles; tapping every %.1f s", static_cast<long>(rest.numVertices()),
           static_cast<long>(rest.numTriangles()), period);

  const ros::Time start = ros::Time::now();
  ros::Rate loop(rate);
  while (ros::ok()) {
    header.stamp = ros::Time::now();
    const ToolState tool = scriptedTool((header.stamp - start).toSec(), period, maxDepth);
    Eigen::Matrix3Xf positions = rest.vertices.cast<float>();
    for (Eigen::Index v = 0; v < rest.numVertices(); ++v) {
      const Eigen::Vector3d x = rest.vertices.col(v);
      const double falloff = std::exp(-(x.head<2>() - tool.xy).squaredNorm() / (2 * dentRadius * dentRadius));
      positions(2, v) -= static_cast<float>(tool.depth * falloff * x.z() / thickness);  // bottom stays fixed
    }
    de::ToolContactArray contacts;
    contacts.header = header;
    if (tool.depth > 0.0) {
      de::ToolContact contact;
      contact.header = header;
      contact.tool_id = "demo_tool";
      contact.in_contact = true;
      contact.position.x = tool.xy.x();
      contact.position.y = tool.xy.y();
      contact.position.z = thickness - tool.depth;
      contact.normal.z = 1.0;
      contacts.contacts.push_back(contact);
    }
    contactsPub.publish(contacts);
    statePub.publish(de::ros_layer::cloudFromPositions(positions, header));
    ros::spinOnce();
    loop.sleep();
  }
  return 0;
}
