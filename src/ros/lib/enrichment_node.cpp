#include "deformation_enrichment/ros/enrichment_node.hpp"

#include <algorithm>

#include "deformation_enrichment/descriptors/site_segmentation.hpp"
#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/ros/conversions.hpp"
#include "deformation_enrichment/ros/site_regions.hpp"

namespace deformation_enrichment::ros_layer {

EnrichmentNode::EnrichmentNode(ros::NodeHandle nh, ros::NodeHandle privateNh)
    : nh_(nh),
      privateNh_(privateNh),
      parameters_(readEnrichmentNodeOptions(privateNh)),
      tfListener_(tfBuffer_, nh),
      counters_(parameters_.errorThrottle),
      diagnostics_(nh, privateNh),
      contacts_(tfBuffer_, ros::Duration(parameters_.contactTimeout)) {
  std::optional<enrichment::RestGeometry> rest = startupRest();
  enrichment::SessionOptions options = parameters_.session;
  options.log = [](enrichment::SessionLogLevel level, const std::string& text) {
    if (level == enrichment::SessionLogLevel::Error) ROS_ERROR("%s", text.c_str());
    else if (level == enrichment::SessionLogLevel::Warning) ROS_WARN("%s", text.c_str());
    else ROS_INFO("%s", text.c_str());
  };
  session_ = std::make_unique<enrichment::EnrichmentSession>(std::move(options));
  session_->setKnobs(parameters_.knobs);  // checked by readEnrichmentNodeOptions
  if (rest) {
    try {
      session_->setRestGeometry(std::move(*rest));
    } catch (const Error& e) {
      ROS_ERROR("rest surface rejected: %s (waiting for the rest_mesh topic instead)", e.what());
    }
  }

  diagnostics_.setHardwareID("none");
  diagnostics_.add("enrichment", this, &EnrichmentNode::diagnose);
  outputRate_ = std::make_unique<diagnostic_updater::HeaderlessTopicDiagnostic>(
      "enriched_mesh_state", diagnostics_,
      diagnostic_updater::FrequencyStatusParam(&parameters_.minRate, &parameters_.maxRate, 0.1, 10));
  enrichedPub_ = nh_.advertise<sensor_msgs::PointCloud2>("enriched_mesh_state", 2);
  statusPub_ = privateNh_.advertise<EnrichmentStatus>("status", 10);
  markers_ = std::make_unique<MarkerPublisher>(
      nh_, privateNh_, parameters_.markerRate, parameters_.markers,
      [this](Eigen::Index vertices) { return session_->restFor(vertices); },
      [this](const std::string& input, const std::string& reason, const std::string& detail) { reject(input, reason, detail); });
  // No transport hints: nodelets then receive the publisher's shared pointer (zero copy).
  restMeshSub_ = nh_.subscribe("rest_mesh", 1, &EnrichmentNode::onRestMesh, this);
  // Deep enough to ride out a stall of the host (100 ms at 60 Hz), short enough to bound the latency.
  meshStateSub_ = nh_.subscribe("mesh_state", parameters_.stateQueueSize, &EnrichmentNode::onMeshState, this);
  contactsSub_ = nh_.subscribe("contacts", 10, &EnrichmentNode::onContacts, this);
  tools_ = std::make_unique<ToolPoseInput>(nh_, parameters_.toolPoses, parameters_.robotDescription,
                                           [this](const std::string& input, const std::string& reason,
                                                  const std::string& detail) { reject(input, reason, detail); });

  siteRegionsPub_ = privateNh_.advertise<visualization_msgs::MarkerArray>("site_regions", 1, /*latch=*/true);
  ros::NodeHandle serviceNh(privateNh_);
  serviceNh.setCallbackQueue(&serviceQueue_);
  segmentSitesService_ = serviceNh.advertiseService("segment_sites", &EnrichmentNode::onSegmentSites, this);
  loadExampleSetService_ = serviceNh.advertiseService("load_example_set", &EnrichmentNode::onLoadExampleSet, this);
  serviceSpinner_ = std::make_unique<ros::AsyncSpinner>(1, &serviceQueue_);
  serviceSpinner_->start();

  if (!parameters_.exampleSet.empty()) {
    try {
      loadExampleSet(parameters_.exampleSet);
    } catch (const Error& e) {
      ROS_ERROR("example set '%s' rejected: %s (enriching nothing until one loads)", parameters_.exampleSet.c_str(), e.what());
    }
  }
  // Its service runs on the service queue too, so reconfiguring never stalls the enrichment; the callback
  // runs once here with the parameters' values.
  reconfigureServer_ = std::make_unique<dynamic_reconfigure::Server<EnrichmentConfig>>(reconfigureMutex_, serviceNh);
  reconfigureServer_->setCallback([this](EnrichmentConfig& config, uint32_t level) { onReconfigure(config, level); });

  diagnosticsTimer_ = nh_.createTimer(ros::Duration(0.5), [this](const ros::TimerEvent&) { diagnostics_.update(); });
  masterWatch_ = std::make_unique<MasterWatch>(privateNh_, parameters_.masterCheckPeriod);
}

void EnrichmentNode::onRestMesh(const pcl_msgs::PolygonMeshConstPtr& message) {
  try {
    // The scene's volume holds every rest surface of the object (a cut surface too).
    session_->setRestGeometry({triangleMeshFromMessage(*message), sceneVolume_, "topic rest_mesh"});
  } catch (const Error& e) {
    std::lock_guard<std::mutex> lock(mutex_);
    reject("rest_mesh", "refused", e.what());
  }
}

void EnrichmentNode::onMeshState(const ros::MessageEvent<const sensor_msgs::PointCloud2>& event) {
  const auto start = std::chrono::steady_clock::now();
  const sensor_msgs::PointCloud2ConstPtr& message = event.getConstMessage();
  std::lock_guard<std::mutex> lock(mutex_);
  counters_.stateIn(event.getPublisherName(), message->header.seq);
  Eigen::Matrix3Xf& positions = state_;  // reused: no allocation per state
  try {
    positionsFromCloud(*message, positions);
  } catch (const Error& e) {
    return reject("mesh_state", "invalid point cloud", e.what());
  }
  const std::shared_ptr<const enrichment::RestSurface> rest = session_->restFor(positions.cols());
  if (!rest) {
    const auto newest = session_->newestRest();
    if (!newest) return reject("mesh_state", "no rest mesh yet", "publish rest_mesh or set ~scene or ~rest_mesh_file");
    return reject("mesh_state", "point count differs from the rest mesh",
                  std::to_string(positions.cols()) + " points, the rest mesh has " +
                      std::to_string(newest->geometry.surface.numVertices()) + " vertices");
  }
  meshFrame_ = message->header.frame_id;
  tools_->resolve(message->header.stamp, meshFrame_, positions, *rest, parameters_.toolContactDistance, contacts_);
  std::vector<TrackedContact> touching = contacts_.active(message->header.stamp);
  std::vector<enrichment::ToolContact> tools;
  for (const TrackedContact& contact : touching) tools.push_back({contact.toolId, contact.position});
  try {
    const enrichment::FrameResult& result = session_->enrich(positions, tools, message->header.stamp.toSec());
    if (!result.error.empty()) reject("contacts", "enrichment skipped for this state", result.error);
    publish(message, result, touching, start);
  } catch (const InvalidInputError& e) {
    reject("mesh_state", "invalid mesh state", e.what());
  } catch (const Error& e) {
    reject("mesh_state", "enrichment failed", e.what());
  }
}

void EnrichmentNode::publish(const sensor_msgs::PointCloud2ConstPtr& message, const enrichment::FrameResult& result,
                             const std::vector<TrackedContact>& touching, std::chrono::steady_clock::time_point start) {
  sensor_msgs::PointCloud2ConstPtr enriched = message;  // nothing changed: the input itself, without a copy
  if (result.changed) {
    auto copy = boost::make_shared<sensor_msgs::PointCloud2>(*message);
    writePositions(session_->enrichedPositions(), *copy);
    enriched = copy;
  }
  enrichedPub_.publish(enriched);
  outputRate_->tick();
  markers_->keep(message, enriched, touching);

  EnrichmentStatus status;
  status.header = message->header;
  status.vertices_touched = result.verticesTouched;
  status.released_sites = result.releasedSites;
  status.confidence = result.confidence;
  status.example_ids = result.exampleIds;
  status.weights = result.weights;
  status.reused = result.kind == enrichment::FrameResult::Kind::Reused;
  status.rest_building = result.restPending;
  status.states_reused = session_->diagnostics().statesReused;
  for (const auto& contact : touching) status.tool_ids.push_back(contact.toolId);
  const double computeMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  counters_.stateOut(computeMs);
  status.compute_ms = static_cast<float>(computeMs);
  statusPub_.publish(status);
}

void EnrichmentNode::onContacts(const ToolContactArrayConstPtr& message) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (meshFrame_.empty()) return reject("contacts", "no mesh state yet", "no mesh frame to place contacts in");
  try {
    contacts_.updateFromArray(*message, meshFrame_);
  } catch (const Error& e) {
    reject("contacts", "invalid contact", e.what());
  }
}

bool EnrichmentNode::onSegmentSites(SegmentSites::Request& request, SegmentSites::Response& response) {
  const std::shared_ptr<const enrichment::RestSurface> rest = session_->newestRest();
  std_msgs::Header header;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    header.frame_id = meshFrame_;
  }
  response.success = false;
  if (!rest) {
    response.message = "no rest mesh yet";
    return true;
  }
  const auto vertices = static_cast<uint64_t>(rest->geometry.surface.numVertices());
  if (request.regions < 1 || request.regions > vertices) {
    response.message = "segment_sites: regions must be in [1, " + std::to_string(vertices) + "] (one per rest vertex at most), got " +
                       std::to_string(request.regions);
    ROS_ERROR("%s", response.message.c_str());
    return true;
  }
  try {
    // The rest surface's own site density (its interior, the scene's volume or a shell), as the enricher's.
    const double scale = parameters_.segmentationScale;
    const descriptors::SiteDensityOptions density =
        descriptors::forWindow(parameters_.session.density, scale, parameters_.session.defaults.sampleSpacing);
    const mesh::TetMesh* volume = rest->geometry.volume ? &*rest->geometry.volume : nullptr;
    const std::vector<int> labels =
        descriptors::segmentSurface(rest->geometry.surface, volume, static_cast<int>(request.regions), scale, density);
    response.labels.assign(labels.begin(), labels.end());
    header.stamp = ros::Time::now();
    siteRegionsPub_.publish(siteRegionMarkers(header, rest->geometry.surface, labels));
    response.success = true;
    response.message = "segmented " + std::to_string(labels.size()) + " vertices into " +
                       std::to_string(request.regions) + " site regions";
  } catch (const Error& e) {
    response.message = e.what();
    ROS_ERROR("segment_sites failed: %s", e.what());
  }
  return true;
}

void EnrichmentNode::diagnose(diagnostic_updater::DiagnosticStatusWrapper& status) {
  const enrichment::SessionDiagnostics session = session_->diagnostics();
  const enrichment::KnobOptions knobs = session_->knobs();
  std::lock_guard<std::mutex> lock(mutex_);
  counters_.report(status, session.restVertices == 0 && !session.rebuilding);
  status.add("rest vertices", session.restVertices);
  status.add("site density", session.siteDensity);
  status.add("rest surface being built", session.rebuilding);
  status.add("rest surfaces built", session.rebuilds);
  status.add("rest surfaces superseded while building", session.supersededRebuilds);
  status.add("last rest build [s]", session.lastRebuildSeconds);
  status.add("last rest surface refused", session.lastRestError);
  status.add("states reused (unchanged input)", session.statesReused);
  status.add("mesh state queue size", parameters_.stateQueueSize);
  std::string refused;
  for (const std::string& r : parameters_.refusedParameters) refused += (refused.empty() ? "" : ", ") + r;
  status.add("parameters refused at start-up (defaults used)", refused.empty() ? "none" : refused);
  status.add("blend requested", enrichment::toString(knobs.blend));
  status.add("blend", session.blend);
  status.add("material similarity", session.materialSimilarity);
  status.add("stamp scale (similarity or ~transfer_gain)", session.stampScale);
  status.add("stamp gain", knobs.gain.stampGain);
  status.add("min confidence", knobs.gain.minConfidence);
  status.add("max weight norm (0 = no bound)", knobs.gain.maxWeightNorm);
  status.add("rim band", parameters_.session.defaults.rimBand);
  status.add("magnitude aware", parameters_.session.defaults.magnitudeAware ? "true" : "false");
  status.add("rbf lambda", parameters_.session.blending.lambda);
  status.add("cross-validated gain", parameters_.session.blending.crossValidatedGain ? "true" : "false");
  status.add("hermite order requested (0 = set's)", knobs.hermiteOrder);
  if (session.hermiteOrder > 0) {
    status.add("hermite order", session.hermiteOrder);
    status.add("sigma_rho", session.widths.sigmaRho);
    status.add("sigma_u", session.widths.sigmaU);
    status.add("sigma_rho fitted", session.fittedWidths.sigmaRho);
    status.add("sigma_u fitted", session.fittedWidths.sigmaU);
  }
  tools_->report(status);
}

}  // namespace deformation_enrichment::ros_layer
