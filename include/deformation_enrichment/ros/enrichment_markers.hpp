#pragma once
// rviz markers of the enrichment: the enriched surface coloured by the displacement the enrichment
// added, and the tool contacts with their normals.
#include <visualization_msgs/MarkerArray.h>

#include <Eigen/Core>
#include <vector>

#include "deformation_enrichment/mesh/triangle_mesh.hpp"
#include "deformation_enrichment/ros/contact_tracker.hpp"

namespace deformation_enrichment::ros_layer {

struct MarkerOptions {
  int maxTriangles = 50000;           ///< larger surfaces are decimated (every k-th triangle) for rviz
  double displacementScale = 0.002;   ///< added displacement [m] shown as full red
};

visualization_msgs::MarkerArray enrichmentMarkers(const std_msgs::Header& header, const mesh::TriangleMesh& rest,
                                                  const Eigen::Matrix3Xf& input, const Eigen::Matrix3Xf& enriched,
                                                  const std::vector<TrackedContact>& contacts,
                                                  const MarkerOptions& options);

}  // namespace deformation_enrichment::ros_layer
