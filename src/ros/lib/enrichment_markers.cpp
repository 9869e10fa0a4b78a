#include "deformation_enrichment/ros/enrichment_markers.hpp"

#include <algorithm>

namespace deformation_enrichment::ros_layer {
namespace {

std_msgs::ColorRGBA heatColor(double t) {  // 0 -> grey-blue, 1 -> red
  t = std::clamp(t, 0.0, 1.0);
  std_msgs::ColorRGBA color;
  color.r = static_cast<float>(0.55 + 0.45 * t);
  color.g = static_cast<float>(0.6 * (1.0 - t));
  color.b = static_cast<float>(0.75 * (1.0 - t));
  color.a = 1.0f;
  return color;
}

geometry_msgs::Point point(const Eigen::Vector3f& p) {
  geometry_msgs::Point result;
  result.x = p.x();
  result.y = p.y();
  result.z = p.z();
  return result;
}

}  // namespace

visualization_msgs::MarkerArray enrichmentMarkers(const std_msgs::Header& header, const mesh::TriangleMesh& rest,
                                                  const Eigen::Matrix3Xf& input, const Eigen::Matrix3Xf& enriched,
                                                  const std::vector<TrackedContact>& contacts,
                                                  const MarkerOptions& options) {
  visualization_msgs::MarkerArray array;
  visualization_msgs::Marker surface;
  surface.header = header;
  surface.ns = "enriched_surface";
  surface.type = visualization_msgs::Marker::TRIANGLE_LIST;
  surface.action = visualization_msgs::Marker::ADD;
  surface.pose.orientation.w = 1.0;
  surface.scale.x = surface.scale.y = surface.scale.z = 1.0;
  const Eigen::VectorXf added = (enriched - input).colwise().norm();
  const Eigen::Index stride = std::max<Eigen::Index>(1, (rest.numTriangles() + options.maxTriangles - 1) /
                                                            std::max(1, options.maxTriangles));
  for (Eigen::Index t = 0; t < rest.numTriangles(); t += stride) {
    for (int k = 0; k < 3; ++k) {
      const int v = rest.triangles(k, t);
      surface.points.push_back(point(enriched.col(v)));
      surface.colors.push_back(heatColor(added[v] / options.displacementScale));
    }
  }
  array.markers.push_back(surface);

  visualization_msgs::Marker points;
  points.header = header;
  points.ns = "contacts";
  points.type = visualization_msgs::Marker::SPHERE_LIST;
  points.action = contacts.empty() ? visualization_msgs::Marker::DELETE : visualization_msgs::Marker::ADD;
  points.pose.orientation.w = 1.0;
  points.scale.x = points.scale.y = points.scale.z = 0.003;
  points.color.g = 1.0f;
  points.color.a = 1.0f;
  for (const auto& contact : contacts) points.points.push_back(point(contact.position.cast<float>()));
  array.markers.push_back(points);

  visualization_msgs::Marker normals;
  normals.header = header;
  normals.ns = "contact_normals";
  normals.type = visualization_msgs::Marker::LINE_LIST;
  normals.action = points.action;
  normals.pose.orientation.w = 1.0;
  normals.scale.x = 0.0005;
  normals.color.g = 1.0f;
  normals.color.b = 1.0f;
  normals.color.a = 1.0f;
  for (const auto& contact : contacts) {
    normals.points.push_back(point(contact.position.cast<float>()));
    normals.points.push_back(point((contact.position + 0.01 * contact.normal).cast<float>()));
  }
  array.markers.push_back(normals);
  return array;
}

}  // namespace deformation_enrichment::ros_layer
