#include "deformation_enrichment/ros/enrichment_node_parameters.hpp"

#include <ros/console.h>

#include <algorithm>
#include <cmath>
#include <tuple>
#include <vector>

#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::ros_layer {
namespace {

// ~name as a double that `valid` accepts, else `fallback` (logged).
template <typename Valid>
double checked(const ros::NodeHandle& nh, const char* name, double fallback, Valid valid, const char* expected) {
  const double value = nh.param(name, fallback);
  if (valid(value)) return value;
  ROS_ERROR("~%s must be %s, got %g: using %g", name, expected, value, fallback);
  return fallback;
}

bool positive(double v) { return v > 0.0 && std::isfinite(v); }
bool nonNegative(double v) { return v >= 0.0 && std::isfinite(v); }

void readSession(const ros::NodeHandle& nh, EnrichmentNodeOptions& p) {
  enrichment::ContactEnricherOptions& defaults = p.session.defaults;
  p.segmentationScale = checked(nh, "descriptor_scale", p.segmentationScale, positive, "positive");
  defaults.descriptors.window.scale = p.segmentationScale;
  defaults.sampleSpacing = checked(nh, "segmentation_sample_spacing", 0.0, nonNegative, ">= 0 (0: h / 4)");
  enrichment::ContactContinuityOptions continuity;
  continuity.followRelease = nh.param("follow_release", true);
  continuity.releaseFloor = nh.param("release_floor", continuity.releaseFloor);
  continuity.matchRadius = nh.param("site_match_radius", continuity.matchRadius);
  try {
    enrichment::ContactContinuity check(continuity);
    p.session.continuity = continuity;
  } catch (const Error& e) {
    ROS_ERROR("~release_floor or ~site_match_radius rejected: %s (keeping %g and %g)", e.what(),
              p.session.continuity.releaseFloor, p.session.continuity.matchRadius);
    p.session.continuity.followRelease = continuity.followRelease;
  }
  descriptors::SiteDensityOptions& density = p.session.density;
  const std::string source = nh.param<std::string>("site_density", "auto");
  try {
    density.source = descriptors::parseSiteDensitySource(source);
  } catch (const Error& e) {
    ROS_ERROR("~site_density: %s; using auto", e.what());
  }
  density.shellThickness = checked(nh, "shell_thickness", 0.0, nonNegative, ">= 0 (0: three window scales)");
  // What de_evaluate's --rim-band, --correlation-only, --lambda and --no-cv-gain score, for the node.
  defaults.rimBand = checked(nh, "rim_band", defaults.rimBand, [](double v) { return v >= 0.0 && v < 1.0; }, "in [0, 1)");
  defaults.magnitudeAware = nh.param("magnitude_aware", defaults.magnitudeAware);
  p.session.blending.lambda = checked(nh, "rbf_lambda", p.session.blending.lambda, positive, "positive");
  p.session.blending.crossValidatedGain = nh.param("cross_validated_gain", p.session.blending.crossValidatedGain);
  if (nh.hasParam("max_outside")) p.maxOutside = checked(nh, "max_outside", density.maxOutside, nonNegative, ">= 0");
}

void readKnobs(const ros::NodeHandle& nh, enrichment::KnobOptions& k) {
  // Start-up values; the reconfigure server reads the same parameters (its ranges apply later).
  const std::string blend = nh.param<std::string>("blend", enrichment::toString(k.blend));
  try {
    k.blend = enrichment::parseBlendMethod(blend);
  } catch (const Error& e) {
    ROS_ERROR("~blend: %s; using %s", e.what(), enrichment::toString(k.blend));
  }
  k.gain.stampGain = checked(nh, "stamp_gain", k.gain.stampGain, nonNegative, ">= 0");
  k.sigmaRho = checked(nh, "sigma_rho", k.sigmaRho, [](double v) { return std::isfinite(v); }, "finite");
  k.sigmaU = checked(nh, "sigma_u", k.sigmaU, [](double v) { return std::isfinite(v); }, "finite");
  k.hermiteOrder = nh.param("hermite_order", k.hermiteOrder);
  if (k.hermiteOrder < 0) {
    ROS_ERROR("~hermite_order must be >= 0 (0: the set's), got %d: using 0", k.hermiteOrder);
    k.hermiteOrder = 0;
  }
  k.gain.minConfidence = checked(nh, "min_confidence", k.gain.minConfidence, [](double v) { return v >= 0.0 && v <= 1.0; }, "in [0, 1]");
  k.temporalSmoothing = checked(nh, "temporal_smoothing", k.temporalSmoothing, nonNegative, ">= 0");
}

// ~tool_poses, else the default pair of topics; ~robot_description when a tip link needs it.
void readToolPoses(const ros::NodeHandle& nh, EnrichmentNodeOptions& p) {
  p.toolPoses = defaultToolPoseSpecs(p.toolPoseId, p.toolTipLink);
  XmlRpc::XmlRpcValue list;
  if (nh.getParam("tool_poses", list)) {
    try {
      std::vector<ToolPoseSpec> listed = toolPoseSpecs(list);
      if (!listed.empty()) p.toolPoses = std::move(listed);
    } catch (const Error& e) {
      ROS_ERROR("%s: subscribing tool_pose and tool_transform instead", e.what());
    }
  }
  const bool needsUrdf = std::any_of(p.toolPoses.begin(), p.toolPoses.end(), [](const ToolPoseSpec& s) { return !s.tipLink.empty(); });
  std::string key, urdf;
  if (needsUrdf && nh.searchParam("robot_description", key) && nh.getParam(key, urdf)) p.robotDescription = urdf;
}

// Where a surface is drawn beside the enriched one: [x, y, z] in metres; zero (not drawn) when absent or bad.
Eigen::Vector3d markerOffset(const ros::NodeHandle& privateNh, const std::string& name, const char* surface) {
  if (!privateNh.hasParam(name)) return Eigen::Vector3d::Zero();
  std::vector<double> offset;
  if (privateNh.getParam(name, offset) && offset.size() == 3 &&
      std::all_of(offset.begin(), offset.end(), [](double v) { return std::isfinite(v); }))
    return Eigen::Vector3d(offset[0], offset[1], offset[2]);
  // rosrun's _name:=[x, y, z] arrives as a string: roscpp parses only numbers and booleans there.
  ROS_ERROR("~%s must be a list [x, y, z] in metres (finite; from rosrun: rosparam set first); not drawing %s", name.c_str(),
            surface);
  return Eigen::Vector3d::Zero();
}

}  // namespace

MarkerOptions readMarkerOptions(const ros::NodeHandle& privateNh) {
  MarkerOptions options;
  options.maxTriangles = privateNh.param("marker_max_triangles", options.maxTriangles);
  options.displacementScale = privateNh.param("marker_displacement_scale", options.displacementScale);
  options.strainScale = privateNh.param("marker_strain_scale", options.strainScale);
  for (auto [name, scale, fallback] : {std::tuple{"marker_displacement_scale", &options.displacementScale, MarkerOptions().displacementScale},
                                       std::tuple{"marker_strain_scale", &options.strainScale, MarkerOptions().strainScale}})
    if (!(*scale > 0.0 && std::isfinite(*scale))) {
      ROS_ERROR("~%s must be positive and finite, got %g: using %g", name, *scale, fallback);
      *scale = fallback;
    }
  const std::string color = privateNh.param<std::string>("marker_color", "displacement");
  if (color == "strain") options.color = MarkerOptions::Color::Strain;
  else if (color != "displacement")
    ROS_ERROR("~marker_color '%s' is neither 'displacement' nor 'strain': showing the displacement", color.c_str());
  options.coarseOffset = markerOffset(privateNh, "marker_coarse_offset", "the coarse surface");
  options.fineOffset = markerOffset(privateNh, "marker_fine_offset", "the fine truth");
  options.fineStampTolerance = checked(privateNh, "marker_fine_tolerance", options.fineStampTolerance, nonNegative, ">= 0");
  return options;
}

EnrichmentNodeOptions readEnrichmentNodeOptions(const ros::NodeHandle& nh) {
  EnrichmentNodeOptions p;
  p.scene = nh.param<std::string>("scene", "");
  p.restMeshFile = nh.param<std::string>("rest_mesh_file", "");
  p.exampleSet = nh.param<std::string>("example_set", "");
  readKnobs(nh, p.knobs);
  readSession(nh, p);
  p.contactTimeout = checked(nh, "contact_timeout", p.contactTimeout, positive, "positive");
  p.toolContactDistance = checked(nh, "tool_contact_distance", p.toolContactDistance, nonNegative, ">= 0");
  p.toolPoseId = nh.param<std::string>("tool_pose_id", p.toolPoseId);
  p.toolTipLink = nh.param<std::string>("tool_tip_link", "");
  readToolPoses(nh, p);
  p.markers = readMarkerOptions(nh);
  p.markerRate = checked(nh, "marker_rate", p.markerRate, nonNegative, ">= 0 (0: no markers)");
  p.errorThrottle = checked(nh, "error_throttle", p.errorThrottle, nonNegative, ">= 0");
  p.masterCheckPeriod = checked(nh, "master_check_period", p.masterCheckPeriod, nonNegative, ">= 0 (0: never)");
  XmlRpc::XmlRpcValue queueSize;  // read untyped: a double or a string would otherwise be ignored silently
  if (nh.getParam("state_queue_size", queueSize)) {
    if (queueSize.getType() == XmlRpc::XmlRpcValue::TypeInt && static_cast<int>(queueSize) >= 1)
      p.stateQueueSize = static_cast<int>(queueSize);
    else
      ROS_ERROR("~state_queue_size must be a whole number >= 1, got %s: using %d", queueSize.toXml().c_str(), p.stateQueueSize);
  }
  p.minRate = checked(nh, "expected_rate_min", p.minRate, nonNegative, ">= 0");
  p.maxRate = checked(nh, "expected_rate_max", p.maxRate, [&](double v) { return v >= p.minRate && std::isfinite(v); },
                      ">= expected_rate_min");
  return p;
}

}  // namespace deformation_enrichment::ros_layer
