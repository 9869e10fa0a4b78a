#pragma once
// Site segmentation of the rest surface for the SegmentSites service ([Seiler14 §6.1]), and its rviz marker.
#include <visualization_msgs/MarkerArray.h>

#include <vector>

#include "deformation_enrichment/mesh/triangle_mesh.hpp"

namespace deformation_enrichment::ros_layer {

struct SiteSegmentationParameters {
  double scale = 0.005;        ///< Hermite window scale h [m]
  double sampleSpacing = 0.0;  ///< interior sample spacing [m]; 0 = h / 4
};

/// One region label per rest vertex: site descriptors of the closed rest surface (volume-sampled interior)
/// clustered by k-means on d_rho. Throws InvalidInputError (open surface, regions out of range, ...).
std::vector<int> segmentRestSurface(const mesh::TriangleMesh& rest, int regions, const SiteSegmentationParameters& p);

/// The rest surface coloured by region (one distinct colour per label).
visualization_msgs::MarkerArray siteRegionMarkers(const std_msgs::Header& header, const mesh::TriangleMesh& rest,
                                                  const std::vector<int>& labels);

}  // namespace deformation_enrichment::ros_layer
