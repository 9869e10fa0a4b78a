#include "deformation_enrichment/ros/enrichment_node_parameters.hpp"

#include <ros/console.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/ros/parameter.hpp"

namespace deformation_enrichment::ros_layer {
namespace {

bool positive(double v) { return v > 0.0 && std::isfinite(v); }
bool nonNegative(double v) { return v >= 0.0 && std::isfinite(v); }

// A check that `parse` accepts the text (it throws Error otherwise).
template <typename Parse>
auto parses(Parse parse) {
  return [parse](const std::string& text) {
    try {
      parse(text);
      return true;
    } catch (const Error&) {
      return false;
    }
  };
}

void readSession(ParameterReader& read, EnrichmentNodeOptions& p) {
  enrichment::ContactEnricherOptions& defaults = p.session.defaults;
  p.segmentationScale = read("descriptor_scale", p.segmentationScale, positive, "positive");
  defaults.descriptors.window.scale = p.segmentationScale;
  defaults.sampleSpacing = read("segmentation_sample_spacing", 0.0, nonNegative, ">= 0 (0: h / 4)");
  enrichment::ContactContinuityOptions continuity;
  continuity.followRelease = read("follow_release", true);
  continuity.releaseFloor = read("release_floor", continuity.releaseFloor);
  continuity.matchRadius = read("site_match_radius", continuity.matchRadius);
  try {
    enrichment::ContactContinuity check(continuity);
    p.session.continuity = continuity;
  } catch (const Error& e) {
    read.refuse("release_floor and site_match_radius", e.what(), std::to_string(continuity.releaseFloor) + " and " +
                std::to_string(continuity.matchRadius), std::to_string(p.session.continuity.releaseFloor) + " and " +
                std::to_string(p.session.continuity.matchRadius));
    p.session.continuity.followRelease = continuity.followRelease;
  }
  descriptors::SiteDensityOptions& density = p.session.density;
  density.source = descriptors::parseSiteDensitySource(
      read("site_density", std::string("auto"), parses(descriptors::parseSiteDensitySource), "auto, surface, volume or shell"));
  density.shellThickness = read("shell_thickness", 0.0, nonNegative, ">= 0 (0: three window scales)");
  p.session.transferGain = read("transfer_gain", 0.0, nonNegative, ">= 0 (0: the material similarity)");
  // What de_evaluate's --rim-band, --correlation-only, --lambda and --no-cv-gain score, for the node.
  defaults.rimBand = read("rim_band", defaults.rimBand, [](double v) { return v >= 0.0 && v < 1.0; }, "in [0, 1)");
  defaults.magnitudeAware = read("magnitude_aware", defaults.magnitudeAware);
  p.session.blending.lambda = read("rbf_lambda", p.session.blending.lambda, positive, "positive");
  p.session.blending.crossValidatedGain = read("cross_validated_gain", p.session.blending.crossValidatedGain);
  if (read.nodeHandle().hasParam("max_outside")) p.maxOutside = read("max_outside", density.maxOutside, nonNegative, ">= 0");
}

void readKnobs(ParameterReader& read, enrichment::KnobOptions& k) {
  // Start-up values; the reconfigure server reads the same parameters (its ranges apply later).
  k.blend = enrichment::parseBlendMethod(
      read("blend", std::string(enrichment::toString(k.blend)), parses(enrichment::parseBlendMethod), "regression or paper"));
  k.gain.stampGain = read("stamp_gain", k.gain.stampGain, nonNegative, ">= 0");
  k.sigmaRho = read("sigma_rho", k.sigmaRho, [](double v) { return std::isfinite(v); }, "finite");
  k.sigmaU = read("sigma_u", k.sigmaU, [](double v) { return std::isfinite(v); }, "finite");
  k.hermiteOrder = read("hermite_order", k.hermiteOrder, [](int v) { return v >= 0; }, ">= 0 (0: the set's)");
  k.gain.minConfidence = read("min_confidence", k.gain.minConfidence, [](double v) { return v >= 0.0 && v <= 1.0; }, "in [0, 1]");
  k.gain.maxWeightNorm = read("max_weight_norm", k.gain.maxWeightNorm, nonNegative, ">= 0 (0: no bound)");
  k.temporalSmoothing = read("temporal_smoothing", k.temporalSmoothing, nonNegative, ">= 0");
}

// ~tool_poses, else the default pair of topics; ~robot_description when a tip link needs it.
void readToolPoses(ParameterReader& read, EnrichmentNodeOptions& p) {
  const ros::NodeHandle& nh = read.nodeHandle();
  p.toolPoses = defaultToolPoseSpecs(p.toolPoseId, p.toolTipLink);
  XmlRpc::XmlRpcValue list;
  if (nh.getParam("tool_poses", list)) {
    try {
      std::vector<ToolPoseSpec> listed = toolPoseSpecs(list);
      if (!listed.empty()) p.toolPoses = std::move(listed);
    } catch (const Error& e) {
      read.refuse("tool_poses", "a list of {topic, id, tip_link}", e.what(), "tool_pose and tool_transform");
    }
  }
  const bool needsUrdf = std::any_of(p.toolPoses.begin(), p.toolPoses.end(), [](const ToolPoseSpec& s) { return !s.tipLink.empty(); });
  std::string key, urdf;
  if (needsUrdf && nh.searchParam("robot_description", key) && nh.getParam(key, urdf)) p.robotDescription = urdf;
}

// Where a surface is drawn beside the enriched one: [x, y, z] in metres; zero (not drawn) when absent or bad.
Eigen::Vector3d markerOffset(ParameterReader& read, const std::string& name) {
  const ros::NodeHandle& privateNh = read.nodeHandle();
  if (!privateNh.hasParam(name)) return Eigen::Vector3d::Zero();
  std::vector<double> offset;
  if (privateNh.getParam(name, offset) && offset.size() == 3 &&
      std::all_of(offset.begin(), offset.end(), [](double v) { return std::isfinite(v); }))
    return Eigen::Vector3d(offset[0], offset[1], offset[2]);
  // rosrun's _name:=[x, y, z] arrives as a string: roscpp parses only numbers and booleans there.
  XmlRpc::XmlRpcValue given;
  privateNh.getParam(name, given);
  read.refuse(name, "a list [x, y, z] in metres (finite; from rosrun: rosparam set first)", describeParameter(given), "not drawn");
  return Eigen::Vector3d::Zero();
}

}  // namespace

MarkerOptions readMarkerOptions(ParameterReader& read) {
  MarkerOptions options;
  options.maxTriangles = read("marker_max_triangles", options.maxTriangles, [](int v) { return v >= 1; }, ">= 1");
  options.displacementScale = read("marker_displacement_scale", options.displacementScale, positive, "positive");
  options.strainScale = read("marker_strain_scale", options.strainScale, positive, "positive");
  const std::string color = read("marker_color", std::string("displacement"),
                                 [](const std::string& c) { return c == "displacement" || c == "strain"; }, "displacement or strain");
  if (color == "strain") options.color = MarkerOptions::Color::Strain;
  options.coarseOffset = markerOffset(read, "marker_coarse_offset");
  options.fineOffset = markerOffset(read, "marker_fine_offset");
  options.fineStampTolerance = read("marker_fine_tolerance", options.fineStampTolerance, nonNegative, ">= 0");
  return options;
}

MarkerOptions readMarkerOptions(const ros::NodeHandle& privateNh) {
  ParameterReader read(privateNh);
  return readMarkerOptions(read);
}

EnrichmentNodeOptions readEnrichmentNodeOptions(const ros::NodeHandle& nh) {
  EnrichmentNodeOptions p;
  ParameterReader read(nh);
  p.scene = read("scene", std::string());
  p.restMeshFile = read("rest_mesh_file", std::string());
  p.exampleSet = read("example_set", std::string());
  readKnobs(read, p.knobs);
  readSession(read, p);
  p.contactTimeout = read("contact_timeout", p.contactTimeout, positive, "positive");
  p.toolContactDistance = read("tool_contact_distance", p.toolContactDistance, nonNegative, ">= 0");
  p.toolPoseId = read("tool_pose_id", p.toolPoseId);
  p.toolTipLink = read("tool_tip_link", std::string());
  readToolPoses(read, p);
  p.markers = readMarkerOptions(read);
  p.markerRate = read("marker_rate", p.markerRate, nonNegative, ">= 0 (0: no markers)");
  p.errorThrottle = read("error_throttle", p.errorThrottle, nonNegative, ">= 0");
  p.masterCheckPeriod = read("master_check_period", p.masterCheckPeriod, nonNegative, ">= 0 (0: never)");
  p.stateQueueSize = read("state_queue_size", p.stateQueueSize, [](int v) { return v >= 1; }, ">= 1");
  p.minRate = read("expected_rate_min", p.minRate, nonNegative, ">= 0");
  p.maxRate = read("expected_rate_max", p.maxRate, [&](double v) { return v >= p.minRate && std::isfinite(v); },
                      ">= expected_rate_min");
  p.refusedParameters = read.refused();
  return p;
}

}  // namespace deformation_enrichment::ros_layer
