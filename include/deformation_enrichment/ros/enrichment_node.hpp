#pragma once
// The enrichment node: ROS around an enrichment::EnrichmentSession (docs/design.md §6). It converts
// messages, resolves tool poses into contacts, fills the session's options from parameters and publishes the
// enriched state, status, markers (only while subscribed) and diagnostics. Bad input is logged and dropped;
// the session keeps the last good state. The same class runs as enrichment_node and inside
// EnrichmentNodelet.
#include <diagnostic_updater/diagnostic_updater.h>
#include <diagnostic_updater/publisher.h>
#include <dynamic_reconfigure/server.h>
#include <pcl_msgs/PolygonMesh.h>
#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_ros/transform_listener.h>

#include <chrono>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "deformation_enrichment/EnrichmentConfig.h"
#include "deformation_enrichment/EnrichmentStatus.h"
#include "deformation_enrichment/LoadExampleSet.h"
#include "deformation_enrichment/SegmentSites.h"
#include "deformation_enrichment/ToolContactArray.h"
#include "deformation_enrichment/enrichment/enrichment_session.hpp"
#include "deformation_enrichment/ros/contact_tracker.hpp"
#include "deformation_enrichment/ros/enrichment_node_parameters.hpp"
#include "deformation_enrichment/ros/marker_publisher.hpp"
#include "deformation_enrichment/ros/master_watch.hpp"
#include "deformation_enrichment/ros/node_counters.hpp"
#include "deformation_enrichment/ros/tool_pose_input.hpp"

namespace deformation_enrichment::ros_layer {

class EnrichmentNode {
public:
  /// `nh` resolves topics (remappable), `privateNh` parameters and private topics.
  EnrichmentNode(ros::NodeHandle nh, ros::NodeHandle privateNh);

private:
  void onRestMesh(const pcl_msgs::PolygonMeshConstPtr& message);
  void onMeshState(const ros::MessageEvent<const sensor_msgs::PointCloud2>& event);
  void onContacts(const ToolContactArrayConstPtr& message);
  /// Publishes the enriched state of `message` (the input itself when nothing changed: nodelets share it),
  /// its status, and keeps what the markers show.
  void publish(const sensor_msgs::PointCloud2ConstPtr& message, const enrichment::FrameResult& result,
               const std::vector<TrackedContact>& touching, std::chrono::steady_clock::time_point start);
  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& status);
  bool onSegmentSites(SegmentSites::Request& request, SegmentSites::Response& response);
  bool onLoadExampleSet(LoadExampleSet::Request& request, LoadExampleSet::Response& response);
  /// Loads a set into the session; throws Error, leaving the previous set active.
  void loadExampleSet(const std::string& path);
  void onReconfigure(EnrichmentConfig& config, uint32_t level);
  /// The rest geometry at start-up: ~scene (surface, units, volume), else ~rest_mesh_file, else none (the
  /// rest_mesh topic). Logs what it uses or why not.
  std::optional<enrichment::RestGeometry> startupRest();
  /// Counts and logs a dropped input (NodeCounters::drop).
  void reject(const std::string& input, const std::string& reason, const std::string& detail) {
    counters_.drop(input, reason, detail);
  }

  ros::NodeHandle nh_, privateNh_;
  EnrichmentNodeOptions parameters_;
  std::optional<mesh::TetMesh> sceneVolume_;  // ~scene's volume: rest meshes from the topic lie in it too
  std::unique_ptr<enrichment::EnrichmentSession> session_;
  tf2_ros::Buffer tfBuffer_;
  tf2_ros::TransformListener tfListener_;

  NodeCounters counters_;  // before tools_: its pose callbacks count drops until they are unsubscribed
  std::unique_ptr<ToolPoseInput> tools_;
  ros::Subscriber restMeshSub_, meshStateSub_, contactsSub_;
  ros::Publisher enrichedPub_, statusPub_, siteRegionsPub_;
  std::unique_ptr<MarkerPublisher> markers_;
  // Slow services run on their own queue and thread, so the enrichment never waits for them.
  ros::CallbackQueue serviceQueue_;
  std::unique_ptr<ros::AsyncSpinner> serviceSpinner_;
  ros::ServiceServer segmentSitesService_, loadExampleSetService_;
  boost::recursive_mutex reconfigureMutex_;
  std::unique_ptr<dynamic_reconfigure::Server<EnrichmentConfig>> reconfigureServer_;
  ros::Timer diagnosticsTimer_;
  diagnostic_updater::Updater diagnostics_;
  std::unique_ptr<diagnostic_updater::HeaderlessTopicDiagnostic> outputRate_;

  std::mutex mutex_;  // nodelet managers call back from several threads; guards everything below
  ContactTracker contacts_;
  std::string meshFrame_;
  Eigen::Matrix3Xf state_;  // the current state's positions (storage reused from state to state)
  std::unique_ptr<MasterWatch> masterWatch_;  // last: stops first
};

}  // namespace deformation_enrichment::ros_layer
