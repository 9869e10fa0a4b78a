#include "deformation_enrichment/ros/site_regions.hpp"

#include <cmath>


namespace deformation_enrichment::ros_layer {

visualization_msgs::MarkerArray siteRegionMarkers(const std_msgs::Header& header, const mesh::TriangleMesh& rest,
                                                  const std::vector<int>& labels) {
  visualization_msgs::Marker marker;
  marker.header = header;
  marker.ns = "site_regions";
  marker.type = visualization_msgs::Marker::TRIANGLE_LIST;
  marker.pose.orientation.w = 1.0;
  marker.scale.x = marker.scale.y = marker.scale.z = 1.0;
  for (Eigen::Index t = 0; t < rest.numTriangles(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const int v = rest.triangles(k, t);
      geometry_msgs::Point point;
      point.x = rest.vertices(0, v);
      point.y = rest.vertices(1, v);
      point.z = rest.vertices(2, v);
      marker.points.push_back(point);
      // Golden-ratio hues keep neighbouring labels apart.
      const double hue = std::fmod(0.61803398875 * labels[static_cast<size_t>(v)], 1.0) * 6.0;
      std_msgs::ColorRGBA color;
      const double x = 1.0 - std::abs(std::fmod(hue, 2.0) - 1.0);
      const double rgb[6][3] = {{1, x, 0}, {x, 1, 0}, {0, 1, x}, {0, x, 1}, {x, 0, 1}, {1, 0, x}};
      const auto& c = rgb[static_cast<int>(hue) % 6];
      color.r = static_cast<float>(c[0]);
      color.g = static_cast<float>(c[1]);
      color.b = static_cast<float>(c[2]);
      color.a = 1.0f;
      marker.colors.push_back(color);
    }
  }
  visualization_msgs::MarkerArray array;
  array.markers.push_back(marker);
  return array;
}

}  // namespace deformation_enrichment::ros_layer
