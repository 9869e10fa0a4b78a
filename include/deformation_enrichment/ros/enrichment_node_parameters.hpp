#pragma once
// Every parameter the enrichment node reads from the parameter server (config/enrichment.yaml documents
// them), read once at start-up and checked: a value out of range is logged with what is used instead, so the
// node always starts. The reconfigurable knobs change later through dynamic_reconfigure.
#include <ros/node_handle.h>

#include <optional>
#include <string>
#include <vector>

#include "deformation_enrichment/enrichment/enrichment_session.hpp"
#include "deformation_enrichment/ros/enrichment_markers.hpp"
#include "deformation_enrichment/ros/tool_pose_sources.hpp"

namespace deformation_enrichment::ros_layer {

struct EnrichmentNodeOptions {
  std::string scene;          ///< ~scene: a shipped scene name or a scene file (surface, units, volume)
  std::string restMeshFile;   ///< ~rest_mesh_file (used when there is no ~scene)
  std::string exampleSet;     ///< ~example_set
  enrichment::KnobOptions knobs;       ///< start-up values of the reconfigurable knobs
  enrichment::SessionOptions session;      ///< window scale, continuity, site density (log not set here)
  std::optional<double> maxOutside;        ///< ~max_outside when set (else the scene's, else 2 mm)
  double segmentationScale = 0.005;        ///< ~descriptor_scale
  double contactTimeout = 0.5;
  double toolContactDistance = 0.003;
  std::string toolPoseId = "tool_pose", toolTipLink;
  std::vector<ToolPoseSpec> toolPoses;     ///< ~tool_poses, else tool_pose and tool_transform of ~tool_pose_id
  std::optional<std::string> robotDescription;  ///< the URDF (robot_description), read when a tip link is set
  MarkerOptions markers;
  double markerRate = 5.0;
  double errorThrottle = 1.0;
  double masterCheckPeriod = 1.0;  ///< ~master_check_period [s]: how often the master is asked (0: never)
  int stateQueueSize = 6;          ///< ~state_queue_size: mesh states that may wait for the enrichment
  double minRate = 1.0, maxRate = 1000.0;
  std::vector<std::string> refusedParameters;  ///< each "name (value given)": logged, the default used instead
};

/// The marker options from ~marker_max_triangles, ~marker_color (displacement | strain; anything else is reported
/// and displacement used), ~marker_displacement_scale, ~marker_strain_scale and ~marker_coarse_offset
/// ([x, y, z]; anything else is reported and leaves the coarse surface off).
MarkerOptions readMarkerOptions(const ros::NodeHandle& privateNh);

/// Reads the private parameters; values of the wrong type or out of range are logged (ROS_ERROR), listed in
/// refusedParameters and replaced by their defaults.
EnrichmentNodeOptions readEnrichmentNodeOptions(const ros::NodeHandle& privateNh);

}  // namespace deformation_enrichment::ros_layer
