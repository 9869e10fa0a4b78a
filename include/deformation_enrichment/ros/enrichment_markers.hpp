#pragma once
// rviz markers of the enrichment: the enriched surface coloured by the displacement the enrichment
// added and shaded, optionally the coarse input surface and the fine truth beside it, a colour bar of the
// scale, and the tool contacts with their normals.
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
  /// Where the fine truth (when there is one: the fine simulation's state for the input) is drawn relative
  /// to the enriched surface [m], coloured by the enriched state's error against it; zero: not drawn.
  Eigen::Vector3d fineOffset = Eigen::Vector3d::Zero();
  /// A state's fine truth is the newest fine state stamped at or before it, at most this much earlier [s]: a
  /// simulator that runs on its own (Bullet) stamps its states itself, while the truth is stamped with the
  /// tool command it belongs to.
  double fineStampTolerance = 0.1;
};

/// Namespaces: enriched_surface, coarse_surface (when options.coarseOffset is not zero), fine_surface (when
/// options.fineOffset is not zero and `fineTruth` is given: |enriched - fine truth| per vertex on the
/// displacement scale), colour_bar, contacts, contact_normals; the enriched surface's triangle list is the
/// first marker. With strain colours and a rest triangle too degenerate for a deformation gradient, the
/// displacement is shown instead (logged). Throws InvalidInputError for a fine truth of another size than
/// `enriched`.
visualization_msgs::MarkerArray enrichmentMarkers(const std_msgs::Header& header, const mesh::TriangleMesh& rest,
                                                  const Eigen::Matrix3Xf& input, const Eigen::Matrix3Xf& enriched,
                                                  const std::vector<TrackedContact>& contacts,
                                                  const MarkerOptions& options, const Eigen::Matrix3Xf* fineTruth = nullptr);

}  // namespace deformation_enrichment::ros_layer
