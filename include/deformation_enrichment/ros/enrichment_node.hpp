#pragma once
// The enrichment node: validates and converts inputs, keeps the last good state, enriches mesh states at
// tool contacts and publishes the enriched state, status, markers (only while subscribed) and diagnostics.
// The same class runs as the standalone enrichment_node and inside EnrichmentNodelet.
#include <diagnostic_updater/diagnostic_updater.h>
#include <diagnostic_updater/publisher.h>
#include <dynamic_reconfigure/server.h>
#include <geometry_msgs/PoseStamped.h>
#include <geometry_msgs/TransformStamped.h>
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

#include "deformation_enrichment/EnrichmentConfig.h"
#include "deformation_enrichment/EnrichmentStatus.h"
#include "deformation_enrichment/LoadExampleSet.h"
#include "deformation_enrichment/SegmentSites.h"
#include "deformation_enrichment/ToolContactArray.h"
#include "deformation_enrichment/enrichment/contact_continuity.hpp"
#include "deformation_enrichment/enrichment/contact_enricher.hpp"
#include "deformation_enrichment/enrichment/temporal_filter.hpp"
#include "deformation_enrichment/examples/example.hpp"
#include "deformation_enrichment/mesh/triangle_mesh.hpp"
#include "deformation_enrichment/ros/contact_tracker.hpp"
#include "deformation_enrichment/ros/enrichment_markers.hpp"
#include "deformation_enrichment/ros/site_regions.hpp"
#include "deformation_enrichment/ros/tool_pose_sources.hpp"
#include "deformation_enrichment/ros/tool_tip.hpp"

namespace deformation_enrichment::ros_layer {

/// The run-time knobs (dynamic_reconfigure, cfg/Enrichment.cfg) as requested.
struct EnrichmentKnobs {
  double stampGain = 1.0;
  double sigmaRho = 0.0, sigmaU = 0.0;  ///< <= 0: the set's leave-one-out fitted width
  int hermiteOrder = 0;                 ///< 0: the order the set was built with
  double minConfidence = 0.0;           ///< ContactEnricherOptions::minConfidence (0 = no gate)
  double temporalSmoothing = 0.0;       ///< TemporalFilter time constant [s] (0 = off)
};

class EnrichmentNode {
public:
  /// `nh` resolves topics (remappable), `privateNh` parameters and private topics.
  EnrichmentNode(ros::NodeHandle nh, ros::NodeHandle privateNh);

private:
  void onRestMesh(const pcl_msgs::PolygonMeshConstPtr& message);
  void onMeshState(const sensor_msgs::PointCloud2ConstPtr& message);
  void onContacts(const ToolContactArrayConstPtr& message);
  /// One tool's pose topic (~tool_poses, or tool_pose and tool_transform) with its tip geometry.
  struct ToolPoseSource {
    ToolPoseSpec spec;
    ToolTip tip;
    std::string tipStatus;  ///< the tip's description, or why the URDF tip was not used
    ros::Subscriber subscriber;
  };
  /// Subscribes the pose topics of ~tool_poses (or the default pair); an unusable list is logged and the
  /// default pair subscribed instead.
  void subscribeToolPoses();
  /// Checks a tool's pose and keeps it as the tool's latest (a bad one is logged and dropped).
  void updateToolPose(const geometry_msgs::PoseStamped& pose, const ToolPoseSource& source);
  /// The contacts of the kept tool poses on the mesh state `positions` (stamped `stamp`), so a contact lies
  /// on the state it goes with however poses and states interleave; a pose stamped over a second after the
  /// state (a rosbag started over) is forgotten.
  void resolveToolPoses(const ros::Time& stamp, const Eigen::Matrix3Xf& positions);
  void onMarkerTimer(const ros::TimerEvent&);
  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& status);
  bool onSegmentSites(SegmentSites::Request& request, SegmentSites::Response& response);
  bool onLoadExampleSet(LoadExampleSet::Request& request, LoadExampleSet::Response& response);
  /// Loads a set and (if a rest mesh is there) builds the enricher for it; throws, leaving the old ones.
  void loadExampleSet(const std::string& path);
  /// A new ContactEnricher for `rest` configured from `set` (window scale, stamp radius and Hermite order
  /// of the set) and the knobs (a Hermite order above the set's is clamped to it; the caller refuses it).
  std::unique_ptr<enrichment::ContactEnricher> makeEnricher(const mesh::TriangleMesh& rest, const examples::ExampleSet& set,
                                                            const EnrichmentKnobs& knobs) const;
  /// Builds the enricher for `set` and `knobs` outside the lock (the enrichment goes on meanwhile) and
  /// installs both; throws on failure, leaving everything as it was. Service thread only.
  void installEnricher(examples::ExampleSet set, const EnrichmentKnobs& knobs);
  void onReconfigure(EnrichmentConfig& config, uint32_t level);
  /// `link`'s collision geometry from robot_description (a point tip for an empty link, or without a
  /// usable URDF, logged); `status` describes which.
  ToolTip loadToolTip(const std::string& link, std::string& status) const;
  /// Whether the state's data, the contacts and the configuration equal those of the last enriched state
  /// (never while the temporal filter runs: its output moves on every state).
  bool unchanged(const sensor_msgs::PointCloud2& message, const std::vector<enrichment::Contact>& contacts) const;
  /// The tools in contact as enricher contacts, each tool keeping its number for the node's lifetime.
  std::vector<enrichment::Contact> touchingContacts(const std::vector<TrackedContact>& active);
  /// Enriches `positions` for `contacts` (continuity, temporal filter) into `enrichedPositions`, `enriched`
  /// and `status`; throws Error, leaving the continuity and filter memory of the last good state.
  void enrichState(const sensor_msgs::PointCloud2ConstPtr& message, const Eigen::Matrix3Xf& positions,
                   const std::vector<enrichment::Contact>& contacts, Eigen::Matrix3Xf& enrichedPositions,
                   sensor_msgs::PointCloud2ConstPtr& enriched, EnrichmentStatus& status);

  void setRestMesh(mesh::TriangleMesh rest, const std::string& source);
  /// Logs (throttled per input and kind of problem) why an input was dropped, and counts it.
  void reject(const std::string& input, const std::string& why);

  ros::NodeHandle nh_, privateNh_;
  tf2_ros::Buffer tfBuffer_;
  tf2_ros::TransformListener tfListener_;
  ContactTracker contacts_;

  // Parameters (documented in config/enrichment.yaml).
  double toolContactDistance_ = 0.003;
  double errorThrottle_ = 1.0;
  EnrichmentKnobs knobs_;  // requested run-time knobs (guarded by mutex_)
  std::vector<std::unique_ptr<ToolPoseSource>> toolSources_;  // stable addresses: the callbacks hold them
  // The latest pose of each tool id (guarded by mutex_), with the source it came from.
  std::map<std::string, std::pair<geometry_msgs::PoseStamped, const ToolPoseSource*>> toolPoses_;
  MarkerOptions markerOptions_;
  SiteSegmentationParameters segmentation_;

  ros::Subscriber restMeshSub_, meshStateSub_, contactsSub_;
  ros::Publisher enrichedPub_, statusPub_, markersPub_, siteRegionsPub_;
  // Slow services run on their own queue and thread, so the enrichment never waits for them.
  ros::CallbackQueue serviceQueue_;
  std::unique_ptr<ros::AsyncSpinner> serviceSpinner_;
  ros::ServiceServer segmentSitesService_, loadExampleSetService_;
  boost::recursive_mutex reconfigureMutex_;
  std::unique_ptr<dynamic_reconfigure::Server<EnrichmentConfig>> reconfigureServer_;
  ros::Timer markerTimer_, diagnosticsTimer_;
  diagnostic_updater::Updater diagnostics_;
  double minRate_ = 1.0, maxRate_ = 1000.0;
  std::unique_ptr<diagnostic_updater::HeaderlessTopicDiagnostic> outputRate_;

  std::mutex mutex_;  // nodelet managers call back from several threads
  std::optional<mesh::TriangleMesh> rest_;
  std::optional<examples::ExampleSet> exampleSet_;              // active set (kept when a load fails)
  std::unique_ptr<enrichment::ContactEnricher> enricher_;       // rest mesh + active set
  enrichment::EnrichmentResult enrichment_;                     // scratch, reused per state
  Eigen::Matrix3Xd restNormals_;
  std::string meshFrame_;
  sensor_msgs::PointCloud2ConstPtr lastInput_;     // last good mesh state
  sensor_msgs::PointCloud2ConstPtr lastEnriched_;  // what was published for it
  Eigen::Matrix3Xf lastPositions_, lastEnrichedPositions_;
  // Unchanged-input reuse: what the last enriched state was computed from, and its status.
  uint64_t restVersion_ = 0;    // bumped by every new rest mesh
  uint64_t configVersion_ = 0;  // bumped by every new enricher, set or knob value
  bool lastWasEnriched_ = false;
  uint64_t lastConfigVersion_ = 0;
  std::vector<enrichment::Contact> lastContacts_;
  // A stream that holds still: frames and released sites per tool, the optional temporal filter.
  enrichment::ContactContinuity continuity_;
  enrichment::TemporalFilter temporalFilter_;
  std::map<std::string, int> toolNumbers_;  // tool id -> the enricher's tool number
  ros::Time lastStateStamp_;
  EnrichmentStatus lastStatus_;

  // Statistics for diagnostics.
  uint64_t statesIn_ = 0, statesOut_ = 0, statesReused_ = 0;
  std::map<std::string, uint64_t> dropped_;  // by input name
  std::string lastError_;
  double lastComputeMs_ = 0.0, maxComputeMs_ = 0.0;
  std::map<std::string, ros::WallTime> lastLogged_;
};

}  // namespace deformation_enrichment::ros_layer
