#pragma once
// The enrichment node: validates and converts inputs, keeps the last good state, enriches mesh states at
// tool contacts and publishes the enriched state, status, markers (only while subscribed) and diagnostics.
// The same class runs as the standalone enrichment_node and inside EnrichmentNodelet.
#include <diagnostic_updater/diagnostic_updater.h>
#include <diagnostic_updater/publisher.h>
#include <geometry_msgs/PoseStamped.h>
#include <pcl_msgs/PolygonMesh.h>
#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_ros/transform_listener.h>

#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "deformation_enrichment/SegmentSites.h"
#include "deformation_enrichment/ToolContactArray.h"
#include "deformation_enrichment/mesh/triangle_mesh.hpp"
#include "deformation_enrichment/ros/contact_tracker.hpp"
#include "deformation_enrichment/ros/enrichment_markers.hpp"
#include "deformation_enrichment/ros/site_regions.hpp"

namespace deformation_enrichment::ros_layer {

class EnrichmentNode {
public:
  /// `nh` resolves topics (remappable), `privateNh` parameters and private topics.
  EnrichmentNode(ros::NodeHandle nh, ros::NodeHandle privateNh);

private:
  void onRestMesh(const pcl_msgs::PolygonMeshConstPtr& message);
  void onMeshState(const sensor_msgs::PointCloud2ConstPtr& message);
  void onContacts(const ToolContactArrayConstPtr& message);
  void onToolPose(const geometry_msgs::PoseStampedConstPtr& message);
  void onMarkerTimer(const ros::TimerEvent&);
  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& status);
  bool onSegmentSites(SegmentSites::Request& request, SegmentSites::Response& response);

  void setRestMesh(mesh::TriangleMesh rest, const std::string& source);
  /// Logs (throttled per input and kind of problem) why an input was dropped, and counts it.
  void reject(const std::string& input, const std::string& why);

  ros::NodeHandle nh_, privateNh_;
  tf2_ros::Buffer tfBuffer_;
  tf2_ros::TransformListener tfListener_;
  ContactTracker contacts_;

  // Parameters (documented in config/enrichment.yaml).
  std::string toolPoseId_;
  double toolContactDistance_ = 0.003;
  MarkerOptions markerOptions_;
  SiteSegmentationParameters segmentation_;

  ros::Subscriber restMeshSub_, meshStateSub_, contactsSub_, toolPoseSub_;
  ros::Publisher enrichedPub_, statusPub_, markersPub_, siteRegionsPub_;
  // Slow services run on their own queue and thread, so the enrichment never waits for them.
  ros::CallbackQueue serviceQueue_;
  std::unique_ptr<ros::AsyncSpinner> serviceSpinner_;
  ros::ServiceServer segmentSitesService_;
  ros::Timer markerTimer_, diagnosticsTimer_;
  diagnostic_updater::Updater diagnostics_;
  double minRate_ = 1.0, maxRate_ = 1000.0;
  std::unique_ptr<diagnostic_updater::HeaderlessTopicDiagnostic> outputRate_;

  std::mutex mutex_;  // nodelet managers call back from several threads
  std::optional<mesh::TriangleMesh> rest_;
  Eigen::Matrix3Xd restNormals_;
  std::string meshFrame_;
  sensor_msgs::PointCloud2ConstPtr lastInput_;     // last good mesh state
  sensor_msgs::PointCloud2ConstPtr lastEnriched_;  // what was published for it
  Eigen::Matrix3Xf lastPositions_, lastEnrichedPositions_;

  // Statistics for diagnostics.
  uint64_t statesIn_ = 0, statesOut_ = 0;
  std::map<std::string, uint64_t> dropped_;  // by input name
  std::string lastError_;
  double lastComputeMs_ = 0.0, maxComputeMs_ = 0.0;
  std::map<std::string, ros::WallTime> lastLogged_;
};

}  // namespace deformation_enrichment::ros_layer
