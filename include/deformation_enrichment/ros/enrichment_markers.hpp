#pragma once
// rviz markers of the enrichment: the enriched surface coloured by the displacement the enrichment
// added and shaded, optionally the coarse input surface beside it, a colour bar of the scale, and the
// tool contacts with their normals.
#include <visualization_msgs/MarkerArray.h>

#include <Eigen/Core>
#include <vector>

#include "deformation_enrichment/mesh/triangle_mesh.hpp"
#include "deformation_enrichment/ros/contact_tracker.hpp"

namespace deformation_enrichment::ros_layer {

struct MarkerOptions {
  /// What the enriched surface's colour shows: the displacement the enrichment added (per vertex), or the
  /// strain of the enriched state, the largest |principal stretch - 1| of each triangle (seed 003).
  enum class Color { Displacement, Strain };
  int maxTriangles = 50000;           ///< larger surfaces are decimated (every k-th triangle) for rviz
  Color color = Color::Displacement;
  double displacementScale = 0.0015;  ///< added displacement [m] shown as full red
  double strainScale = 0.1;           ///< strain shown as full red (0.1 = 10 %)
  /// Where the coarse input surface is drawn relative to the enriched one [m]; zero: not drawn.
  Eigen::Vector3d coarseOffset = Eigen::Vector3d::Zero();
};

/// Namespaces: enriched_surface, coarse_surface (when options.coarseOffset is not zero), colour_bar,
/// contacts, contact_normals; the enriched surface's triangle list is the first marker. With strain colours
/// and a rest triangle too degenerate for a deformation gradient, the displacement is shown instead (logged).
visualization_msgs::MarkerArray enrichmentMarkers(const std_msgs::Header& header, const mesh::TriangleMesh& rest,
                                                  const Eigen::Matrix3Xf& input, const Eigen::Matrix3Xf& enriched,
                                                  const std::vector<TrackedContact>& contacts,
                                                  const MarkerOptions& options);

}  // namespace deformation_enrichment::ros_layer
