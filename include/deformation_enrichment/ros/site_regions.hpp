#pragma once
// The rviz marker of the SegmentSites service: the rest surface coloured by site region ([Seiler14 §6.1];
// the segmentation itself is descriptors::segmentSurface).
#include <visualization_msgs/MarkerArray.h>

#include <vector>

#include "deformation_enrichment/mesh/triangle_mesh.hpp"

namespace deformation_enrichment::ros_layer {

/// The rest surface coloured by region (one distinct colour per label).
visualization_msgs::MarkerArray siteRegionMarkers(const std_msgs::Header& header, const mesh::TriangleMesh& rest,
                                                  const std::vector<int>& labels);

}  // namespace deformation_enrichment::ros_layer
