#include "deformation_enrichment/ros/enrichment_node.hpp"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstring>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/mesh_io.hpp"
#include "deformation_enrichment/mesh/mesh_state.hpp"
#include "deformation_enrichment/ros/conversions.hpp"

namespace deformation_enrichment::ros_layer {

EnrichmentNode::EnrichmentNode(ros::NodeHandle nh, ros::NodeHandle privateNh)
    : nh_(nh),
      privateNh_(privateNh),
      tfListener_(tfBuffer_, nh),
      contacts_(tfBuffer_, ros::Duration(privateNh.param("contact_timeout", 0.5))),
      diagnostics_(nh, privateNh) {
  errorThrottle_ = privateNh_.param("error_throttle", 1.0);
  toolContactDistance_ = privateNh_.param("tool_contact_distance", 0.003);
  markerOptions_ = markerOptionsFromParams(privateNh_);
  segmentation_.scale = privateNh_.param("descriptor_scale", 0.005);
  segmentation_.sampleSpacing = privateNh_.param("segmentation_sample_spacing", 0.0);
  // Start-up values of the run-time knobs; the reconfigure server reads the same parameters.
  knobs_.stampGain = privateNh_.param("stamp_gain", 1.0);
  knobs_.sigmaRho = privateNh_.param("sigma_rho", 0.0);
  knobs_.sigmaU = privateNh_.param("sigma_u", 0.0);
  knobs_.hermiteOrder = privateNh_.param("hermite_order", 0);
  knobs_.minConfidence = privateNh_.param("min_confidence", 0.0);
  knobs_.temporalSmoothing = privateNh_.param("temporal_smoothing", 0.0);
  enrichment::ContactContinuityOptions continuity;
  continuity.followRelease = privateNh_.param("follow_release", true);
  continuity.releaseFloor = privateNh_.param("release_floor", continuity.releaseFloor);
  continuity.matchRadius = privateNh_.param("site_match_radius", continuity.matchRadius);
  try {
    continuity_ = enrichment::ContactContinuity(continuity);
  } catch (const Error& e) {
    ROS_ERROR("~release_floor or ~site_match_radius rejected: %s (keeping %g and %g)", e.what(),
              enrichment::ContactContinuityOptions().releaseFloor, enrichment::ContactContinuityOptions().matchRadius);
  }
  minRate_ = privateNh_.param("expected_rate_min", 1.0);
  maxRate_ = privateNh_.param("expected_rate_max", 1000.0);

  diagnostics_.setHardwareID("none");
  diagnostics_.add("enrichment", this, &EnrichmentNode::diagnose);
  outputRate_ = std::make_unique<diagnostic_updater::HeaderlessTopicDiagnostic>(
      "enriched_mesh_state", diagnostics_, diagnostic_updater::FrequencyStatusParam(&minRate_, &maxRate_, 0.1, 10));

  const std::string restFile = privateNh_.param<std::string>("rest_mesh_file", "");
  if (!restFile.empty()) {
    try {
      setRestMesh(mesh::readTriangleMesh(restFile), "file " + restFile);
    } catch (const Error& e) {
      ROS_ERROR("rest mesh file rejected: %s (waiting for the rest_mesh topic instead)", e.what());
    }
  }

  enrichedPub_ = nh_.advertise<sensor_msgs::PointCloud2>("enriched_mesh_state", 2);
  statusPub_ = privateNh_.advertise<EnrichmentStatus>("status", 10);
  markersPub_ = privateNh_.advertise<visualization_msgs::MarkerArray>("markers", 1);
  // No transport hints: nodelets then receive the publisher's shared pointer (zero copy).
  restMeshSub_ = nh_.subscribe("rest_mesh", 1, &EnrichmentNode::onRestMesh, this);
  meshStateSub_ = nh_.subscribe("mesh_state", 2, &EnrichmentNode::onMeshState, this);
  contactsSub_ = nh_.subscribe("contacts", 10, &EnrichmentNode::onContacts, this);
  subscribeToolPoses();

  siteRegionsPub_ = privateNh_.advertise<visualization_msgs::MarkerArray>("site_regions", 1, /*latch=*/true);
  ros::NodeHandle serviceNh(privateNh_);
  serviceNh.setCallbackQueue(&serviceQueue_);
  segmentSitesService_ = serviceNh.advertiseService("segment_sites", &EnrichmentNode::onSegmentSites, this);
  loadExampleSetService_ = serviceNh.advertiseService("load_example_set", &EnrichmentNode::onLoadExampleSet, this);
  serviceSpinner_ = std::make_unique<ros::AsyncSpinner>(1, &serviceQueue_);
  serviceSpinner_->start();

  const std::string setPath = privateNh_.param<std::string>("example_set", "");
  if (!setPath.empty()) {
    try {
      loadExampleSet(setPath);
    } catch (const Error& e) {
      ROS_ERROR("example set '%s' rejected: %s (enriching nothing until one loads)", setPath.c_str(), e.what());
    }
  }
  // Its service runs on the service queue too, so reconfiguring never stalls the enrichment; the callback
  // runs once here with the parameters' values.
  reconfigureServer_ = std::make_unique<dynamic_reconfigure::Server<EnrichmentConfig>>(reconfigureMutex_, serviceNh);
  reconfigureServer_->setCallback([this](EnrichmentConfig& config, uint32_t level) { onReconfigure(config, level); });

  const double markerRate = privateNh_.param("marker_rate", 5.0);
  if (markerRate > 0.0) markerTimer_ = nh_.createTimer(ros::Duration(1.0 / markerRate), &EnrichmentNode::onMarkerTimer, this);
  diagnosticsTimer_ = nh_.createTimer(ros::Duration(0.5), [this](const ros::TimerEvent&) { diagnostics_.update(); });
}

void EnrichmentNode::reject(const std::string& input, const std::string& why) {
  ++dropped_[input];
  lastError_ = input + ": " + why;
  // Throttle per input and kind of problem (digits stripped), so distinct problems are all reported.
  std::string kind = input + why;
  kind.erase(std::remove_if(kind.begin(), kind.end(), [](unsigned char c) { return std::isdigit(c); }), kind.end());
  const ros::WallTime now = ros::WallTime::now();
  auto& last = lastLogged_[kind];
  if (last.isZero() || (now - last).toSec() >= errorThrottle_) {
    last = now;
    ROS_ERROR("dropped %s: %s (keeping the last good state)", input.c_str(), why.c_str());
  }
}

void EnrichmentNode::setRestMesh(mesh::TriangleMesh rest, const std::string& source) {
  mesh::validate(rest, false);
  // A latched topic re-sends the same mesh to every new connection: keep the state then.
  if (rest_ && rest_->numVertices() == rest.numVertices() && rest_->numTriangles() == rest.numTriangles() &&
      rest_->vertices == rest.vertices && rest_->triangles == rest.triangles)
    return;
  restNormals_ = mesh::vertexNormals(rest);
  ROS_INFO("rest mesh from %s: %ld vertices, %ld triangles", source.c_str(), static_cast<long>(rest.numVertices()),
           static_cast<long>(rest.numTriangles()));
  // A new topology (e.g. after a cut) needs a new enricher; the loaded examples stay.
  if (exampleSet_) {
    try {
      enricher_ = makeEnricher(rest, *exampleSet_, knobs_);
    } catch (const Error& e) {
      enricher_.reset();
      ROS_ERROR("cannot enrich the new rest mesh: %s", e.what());
    }
  }
  rest_ = std::move(rest);
  ++restVersion_;
  ++configVersion_;
  // A new topology invalidates states of the old one, and the tools' memory of it.
  continuity_.reset();
  temporalFilter_.reset();
  lastInput_.reset();
  lastEnriched_.reset();
  lastPositions_.resize(3, 0);
  lastEnrichedPositions_.resize(3, 0);
}

void EnrichmentNode::onRestMesh(const pcl_msgs::PolygonMeshConstPtr& message) {
  std::lock_guard<std::mutex> lock(mutex_);
  try {
    setRestMesh(triangleMeshFromMessage(*message), "topic rest_mesh");
  } catch (const Error& e) {
    reject("rest_mesh", e.what());
  }
}

namespace {
bool sameContact(const enrichment::Contact& a, const enrichment::Contact& b) {
  return a.point == b.point && a.restState == b.restState && a.normal == b.normal && a.toolId == b.toolId &&
         a.previousFrameAxis == b.previousFrameAxis && a.releasedMagnitude == b.releasedMagnitude;
}
}  // namespace

bool EnrichmentNode::unchanged(const sensor_msgs::PointCloud2& message, const std::vector<enrichment::Contact>& contacts) const {
  if (!lastWasEnriched_ || !lastInput_ || lastConfigVersion_ != configVersion_) return false;
  if (temporalFilter_.timeConstant() > 0.0) return false;
  if (contacts.size() != lastContacts_.size() || !std::equal(contacts.begin(), contacts.end(), lastContacts_.begin(), sameContact))
    return false;
  const sensor_msgs::PointCloud2& last = *lastInput_;
  if (message.width != last.width || message.height != last.height || message.point_step != last.point_step ||
      message.is_bigendian != last.is_bigendian || message.fields != last.fields || message.data.size() != last.data.size())
    return false;
  // One pass over the buffer (~0.1 ms per 100k points), far below describing, blending and mapping.
  return std::memcmp(message.data.data(), last.data.data(), message.data.size()) == 0;
}

void EnrichmentNode::onMeshState(const sensor_msgs::PointCloud2ConstPtr& message) {
  const auto start = std::chrono::steady_clock::now();
  std::lock_guard<std::mutex> lock(mutex_);
  ++statesIn_;
  if (!rest_) return reject("mesh_state", "no rest mesh yet (publish rest_mesh or set ~rest_mesh_file)");
  Eigen::Matrix3Xf positions;
  try {
    positions = positionsFromCloud(*message);
    mesh::validateMeshState(positions, rest_->numVertices());
  } catch (const Error& e) {
    return reject("mesh_state", e.what());
  }
  meshFrame_ = message->header.frame_id;
  resolveToolPoses(message->header.stamp, positions);
  const std::vector<TrackedContact> active = contacts_.active(message->header.stamp);

  EnrichmentStatus status;
  status.header = message->header;
  // No contact or no examples: the input itself is the enriched state, published without a copy
  // (nodelet subscribers share the pointer). Otherwise only the touched vertices change.
  sensor_msgs::PointCloud2ConstPtr enriched = message;
  Eigen::Matrix3Xf enrichedPositions = positions;
  // Tools in contact, then the sites released tools left deformed; a fading filter needs states too.
  const std::vector<enrichment::Contact> contacts =
      enricher_ ? continuity_.contactsFor(touchingContacts(active)) : std::vector<enrichment::Contact>();
  const bool enrich = enricher_ && (!contacts.empty() || temporalFilter_.fading());
  bool enrichedHere = false;  // the enrichment ran (or was reused) without error
  if (enrich && unchanged(*message, contacts)) {
    // Same state, contacts, set and knobs as the last enriched state: republish its result, new header.
    if (lastEnriched_ != lastInput_) {
      auto copy = boost::make_shared<sensor_msgs::PointCloud2>(*lastEnriched_);
      copy->header = message->header;
      enriched = copy;
    }
    enrichedPositions = lastEnrichedPositions_;
    status = lastStatus_;
    status.header = message->header;
    status.tool_ids.clear();
    status.reused = true;
    ++statesReused_;
    enrichedHere = true;
  } else if (enrich) {
    try {
      enrichState(message, positions, contacts, enrichedPositions, enriched, status);
      enrichedHere = true;
    } catch (const Error& e) {
      reject("contacts", std::string("enrichment skipped for this state: ") + e.what());
      enriched = message;
      enrichedPositions = positions;
      status = EnrichmentStatus();
      status.header = message->header;
    }
  } else {
    temporalFilter_.reset();  // nothing enriched: a later contact starts the filter afresh
  }
  lastStateStamp_ = message->header.stamp;
  lastWasEnriched_ = enrichedHere;
  lastInput_ = message;
  lastEnriched_ = enriched;
  lastPositions_ = std::move(positions);
  lastEnrichedPositions_ = std::move(enrichedPositions);
  enrichedPub_.publish(lastEnriched_);
  outputRate_->tick();
  ++statesOut_;

  lastComputeMs_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  maxComputeMs_ = std::max(maxComputeMs_, lastComputeMs_);
  for (const auto& contact : active) status.tool_ids.push_back(contact.toolId);
  status.compute_ms = static_cast<float>(lastComputeMs_);
  status.states_reused = statesReused_;
  statusPub_.publish(status);
}

std::vector<enrichment::Contact> EnrichmentNode::touchingContacts(const std::vector<TrackedContact>& active) {
  std::vector<enrichment::Contact> contacts;
  for (const TrackedContact& tracked : active) {
    enrichment::Contact contact;
    contact.point = tracked.position;
    contact.restState = false;  // contacts live in the current (mesh-state) frame
    const auto number = toolNumbers_.emplace(tracked.toolId, static_cast<int>(toolNumbers_.size())).first;
    contact.toolId = number->second;
    contacts.push_back(contact);
  }
  return contacts;
}

void EnrichmentNode::enrichState(const sensor_msgs::PointCloud2ConstPtr& message, const Eigen::Matrix3Xf& positions,
                                 const std::vector<enrichment::Contact>& contacts, Eigen::Matrix3Xf& enrichedPositions,
                                 sensor_msgs::PointCloud2ConstPtr& enriched, EnrichmentStatus& status) {
  const Eigen::Matrix3Xd current = positions.cast<double>();
  enricher_->enrich(current, contacts, enrichment_);
  auto& touched = enrichment_.enrichment;
  const double dt = lastStateStamp_.isZero() ? 0.0 : (message->header.stamp - lastStateStamp_).toSec();
  temporalFilter_.filter(touched, dt, current.cols());  // a dt <= 0 (stamps going backwards) restarts it
  for (size_t k = 0; k < touched.vertices.size(); ++k)
    enrichedPositions.col(touched.vertices[k]) += touched.displacements.col(static_cast<Eigen::Index>(k)).cast<float>();
  if (!enrichedPositions.allFinite()) {
    temporalFilter_.reset();
    throw NumericalError("enrichment produced a non-finite position");
  }
  continuity_.update(enrichment_);
  if (!touched.vertices.empty()) {
    auto copy = boost::make_shared<sensor_msgs::PointCloud2>(*message);
    writePositions(enrichedPositions, *copy);
    enriched = copy;
  }
  status.vertices_touched = static_cast<uint32_t>(touched.vertices.size());
  status.released_sites = static_cast<uint32_t>(continuity_.releasedSites());
  for (const auto& outcome : enrichment_.contacts) {
    status.confidence = std::max(status.confidence, static_cast<float>(outcome.confidence));
    for (Eigen::Index i = 0; i < outcome.weights.size(); ++i) {
      if (std::abs(outcome.weights[i]) < 1e-3) continue;  // report the examples that matter
      status.example_ids.push_back(static_cast<uint32_t>(i));
      status.weights.push_back(static_cast<float>(outcome.weights[i]));
    }
  }
  lastStatus_ = status;
  lastContacts_ = contacts;
  lastConfigVersion_ = configVersion_;
}

void EnrichmentNode::onContacts(const ToolContactArrayConstPtr& message) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (meshFrame_.empty()) return reject("contacts", "no mesh state yet, so no mesh frame to place contacts in");
  try {
    contacts_.updateFromArray(*message, meshFrame_);
  } catch (const Error& e) {
    reject("contacts", e.what());
  }
}

void EnrichmentNode::updateToolPose(const geometry_msgs::PoseStamped& pose, const ToolPoseSource& source) {
  std::lock_guard<std::mutex> lock(mutex_);
  try {
    ContactTracker::linkPose(pose, source.spec.id, source.tip);
    toolPoses_[source.spec.id] = {pose, &source};
  } catch (const Error& e) {
    reject(source.spec.topic, e.what());
  }
}

void EnrichmentNode::resolveToolPoses(const ros::Time& stamp, const Eigen::Matrix3Xf& positions) {
  for (auto it = toolPoses_.begin(); it != toolPoses_.end();) {
    const auto& [pose, source] = it->second;
    if (pose.header.stamp > stamp + ros::Duration(1.0)) {
      it = toolPoses_.erase(it);
      continue;
    }
    try {
      // A URDF tip is measured against the triangles (exact, 1.39 ms at 100k vertices, bench_tool_contact_ros);
      // a point tip against the vertices (0.33 ms), its contact being the tip itself.
      contacts_.updateFromToolPose(pose, source->spec.id, meshFrame_, positions, restNormals_, toolContactDistance_,
                                   source->tip, source->tip.isPoint() ? nullptr : &rest_->triangles);
    } catch (const Error& e) {
      reject(source->spec.topic, e.what());
    }
    ++it;
  }
}

void EnrichmentNode::onMarkerTimer(const ros::TimerEvent&) {
  if (markersPub_.getNumSubscribers() == 0) return;  // markers cost megabytes: only for an audience
  std::lock_guard<std::mutex> lock(mutex_);
  if (!rest_ || !lastInput_) return;
  const auto active = contacts_.active(lastInput_->header.stamp);
  markersPub_.publish(enrichmentMarkers(lastInput_->header, *rest_, lastPositions_, lastEnrichedPositions_, active,
                                        markerOptions_));
}

bool EnrichmentNode::onSegmentSites(SegmentSites::Request& request, SegmentSites::Response& response) {
  std::optional<mesh::TriangleMesh> rest;
  std_msgs::Header header;
  {
    std::lock_guard<std::mutex> lock(mutex_);  // copy, so the enrichment goes on while this computes
    rest = rest_;
    header.frame_id = meshFrame_;
  }
  response.success = false;
  if (!rest) {
    response.message = "no rest mesh yet";
    return true;
  }
  const auto vertices = static_cast<uint64_t>(rest->vertices.cols());
  if (request.regions < 1 || request.regions > vertices) {
    response.message = "segment_sites: regions must be in [1, " + std::to_string(vertices) + "] (one per rest vertex at most), got " +
                       std::to_string(request.regions);
    ROS_ERROR("%s", response.message.c_str());
    return true;
  }
  try {
    const std::vector<int> labels = segmentRestSurface(*rest, static_cast<int>(request.regions), segmentation_);
    response.labels.assign(labels.begin(), labels.end());
    header.stamp = ros::Time::now();
    siteRegionsPub_.publish(siteRegionMarkers(header, *rest, labels));
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
  std::lock_guard<std::mutex> lock(mutex_);
  uint64_t droppedTotal = 0;
  for (const auto& [input, count] : dropped_) {
    status.add("dropped " + input, count);
    droppedTotal += count;
  }
  if (!rest_) {
    status.summary(diagnostic_msgs::DiagnosticStatus::WARN, "waiting for a rest mesh");
  } else if (droppedTotal > 0) {
    status.summary(diagnostic_msgs::DiagnosticStatus::WARN, "inputs dropped; last: " + lastError_);
  } else {
    status.summary(diagnostic_msgs::DiagnosticStatus::OK, "enriching");
  }
  status.add("rest vertices", rest_ ? rest_->numVertices() : 0);
  status.add("mesh states in", statesIn_);
  status.add("enriched states out", statesOut_);
  status.add("last compute [ms]", lastComputeMs_);
  status.add("max compute [ms]", maxComputeMs_);
  status.add("states reused (unchanged input)", statesReused_);
  status.add("last error", lastError_);
  status.add("stamp gain", knobs_.stampGain);
  status.add("hermite order requested (0 = set's)", knobs_.hermiteOrder);
  if (enricher_ && enricher_->blender()) {
    status.add("hermite order", enricher_->options().descriptors.deformationOrder);
    status.add("sigma_rho", enricher_->blender()->widths().sigmaRho);
    status.add("sigma_u", enricher_->blender()->widths().sigmaU);
    status.add("sigma_rho fitted", enricher_->loadedWidths().sigmaRho);
    status.add("sigma_u fitted", enricher_->loadedWidths().sigmaU);
  }
  for (const auto& source : toolSources_) status.add("tool tip of " + source->spec.id + " on " + source->spec.topic, source->tipStatus);
}

}  // namespace deformation_enrichment::ros_layer
