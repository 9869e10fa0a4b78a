#pragma once
// Shared fixture of the enrichment node's rostests: publishers and subscribers for every topic of the
// contract, round trips of mesh states, /rosout capture, the slab surface and a one-example dent set.
#include <gtest/gtest.h>
#include <diagnostic_msgs/DiagnosticArray.h>
#include <geometry_msgs/PoseStamped.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Log.h>
#include <visualization_msgs/MarkerArray.h>

#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <mutex>
#include <string>
#include <vector>

#include "deformation_enrichment/EnrichmentStatus.h"
#include "deformation_enrichment/LoadExampleSet.h"
#include "deformation_enrichment/ToolContactArray.h"
#include "deformation_enrichment/enrichment/contact_enricher.hpp"
#include "deformation_enrichment/examples/example_set_io.hpp"
#include "deformation_enrichment/mesh/grid_tet_mesh.hpp"
#include "deformation_enrichment/mesh/tet_surface.hpp"
#include "deformation_enrichment/ros/conversions.hpp"

namespace de = deformation_enrichment;

namespace enrichment_test {

using de::ros_layer::cloudFromPositions;

/// Spins until `condition` holds or `seconds` of wall time pass; returns the condition's last value.
inline bool waitFor(const std::function<bool()>& condition, double seconds) {
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(seconds);
  while (ros::ok() && ros::WallTime::now() < end) {
    ros::spinOnce();
    if (condition()) return true;
    ros::WallDuration(0.005).sleep();
  }
  ros::spinOnce();
  return condition();
}

inline de::mesh::TriangleMesh slabSurface(int cells) {
  return de::mesh::extractSurface(de::mesh::gridTetMesh(Eigen::Vector3d(-0.05, -0.05, 0), Eigen::Vector3d(0.05, 0.05, 0.02),
                                                        Eigen::Vector3i(cells, cells, 1)))
      .surface;
}

class EnrichmentNodeTest : public ::testing::Test {
protected:
  void SetUp() override {
    restPub_ = nh_.advertise<pcl_msgs::PolygonMesh>("rest_mesh", 1, true);
    statePub_ = nh_.advertise<sensor_msgs::PointCloud2>("mesh_state", 10);
    contactsPub_ = nh_.advertise<de::ToolContactArray>("contacts", 10);
    posePub_ = nh_.advertise<geometry_msgs::PoseStamped>("tool_pose", 10);
    enrichedSub_ = nh_.subscribe("enriched_mesh_state", 10, &EnrichmentNodeTest::onEnriched, this);
    statusSub_ = nh_.subscribe("enrichment/status", 10, &EnrichmentNodeTest::onStatus, this);
    logSub_ = nh_.subscribe("/rosout", 100, &EnrichmentNodeTest::onLog, this);
    diagnosticsSub_ = nh_.subscribe("/diagnostics", 10, &EnrichmentNodeTest::onDiagnostics, this);
    // Messages published before a connection exists are lost: wait for every connection.
    ASSERT_TRUE(waitFor([&] {
      return statePub_.getNumSubscribers() > 0 && contactsPub_.getNumSubscribers() > 0 &&
             posePub_.getNumSubscribers() > 0 && restPub_.getNumSubscribers() > 0 &&
             enrichedSub_.getNumPublishers() > 0 && statusSub_.getNumPublishers() > 0 &&
             logSub_.getNumPublishers() >= 2;  // this test and the enrichment node (or its manager)
    }, 20.0))
        << "the enrichment node did not come up";
    setRest(slabSurface(8));
  }

  std_msgs::Header header() {
    std_msgs::Header h;
    h.frame_id = "slab";
    h.stamp = ros::Time(1000 + (++stampCounter_), 12345);  // unique per message
    return h;
  }

  /// Publishes a state and returns whether an enriched state with its stamp arrived within `seconds`.
  bool roundTrip(const sensor_msgs::PointCloud2& cloud, double seconds = 3.0) {
    statePub_.publish(cloud);
    return waitFor([&] { return findEnriched(cloud.header.stamp) != nullptr; }, seconds);
  }

  /// The status of the state stamped `stamp`, waiting up to `seconds` for it; null if none came.
  de::EnrichmentStatusConstPtr statusFor(const ros::Time& stamp, double seconds = 3.0) {
    de::EnrichmentStatusConstPtr found;
    waitFor([&] {
      std::lock_guard<std::mutex> lock(mutex_);
      for (const auto& s : statuses_)
        if (s->header.stamp == stamp) found = s;
      return found != nullptr;
    }, seconds);
    return found;
  }

  sensor_msgs::PointCloud2ConstPtr findEnriched(const ros::Time& stamp) {
    std::lock_guard<std::mutex> lock(mutex_);
    for (const auto& m : enriched_)
      if (m->header.stamp == stamp) return m;
    return nullptr;
  }

  void setRest(const de::mesh::TriangleMesh& rest) {
    rest_ = rest;
    restPub_.publish(de::ros_layer::messageFromTriangleMesh(rest, header()));
    // The new rest mesh is active once a state of its size goes through and its enricher is built.
    ASSERT_TRUE(waitFor([&] {
      const sensor_msgs::PointCloud2 state = goodState();
      const de::EnrichmentStatusConstPtr status = roundTrip(state, 0.3) ? statusFor(state.header.stamp, 0.3) : nullptr;
      return status && !status->rest_building;
    }, 20.0)) << "rest mesh never became active";
  }

  // A tool pose (as PoseStamped or TransformStamped, sent by `publish`) 1 mm above surface vertex 5 must
  // become the contact of ~tool_pose_id in the status of the next state.
  void expectToolPoseContact(const std::function<void(const Eigen::Vector3d&, const std_msgs::Header&)>& publish) {
    const std_msgs::Header stamped = header();
    publish(rest_.vertices.col(5) + Eigen::Vector3d(0, 0, 0.001), stamped);
    ros::WallDuration(0.3).sleep();
    sensor_msgs::PointCloud2 state = goodState();
    state.header.stamp = stamped.stamp;
    ASSERT_TRUE(roundTrip(state));
    EXPECT_TRUE(waitFor([&] {
      std::lock_guard<std::mutex> lock(mutex_);
      for (const auto& s : statuses_)
        if (s->header.stamp == state.header.stamp && s->tool_ids == std::vector<std::string>{"tool_pose"}) return true;
      return false;
    }, 3.0));
  }

  sensor_msgs::PointCloud2 goodState() { return cloudFromPositions(rest_.vertices.cast<float>(), header()); }

  /// Loads the example set at `path` through the node's service; returns the service's answer.
  de::LoadExampleSet::Response loadSet(const std::string& path) {
    de::LoadExampleSet load;
    load.request.path = path;
    EXPECT_TRUE(ros::service::waitForService("enrichment/load_example_set", 10000));
    EXPECT_TRUE(ros::service::call("enrichment/load_example_set", load));
    return load.response;
  }

  /// Tool PSM1 in contact at the top centre, 2 mm down (where makeDentExampleSet's dent is), published on
  /// `contacts` and given a moment to arrive; returns the message (its header stamps the matching state).
  de::ToolContactArray touchTopCentre() {
    de::ToolContactArray contacts;
    contacts.header = header();
    de::ToolContact tool;
    tool.tool_id = "PSM1";
    tool.in_contact = true;
    tool.position.z = 0.018;
    tool.normal.z = 1.0;
    contacts.contacts.push_back(tool);
    contactsPub_.publish(contacts);
    ros::WallDuration(0.3).sleep();
    return contacts;
  }

  bool logged(const std::string& fragment, double seconds = 3.0) {
    return waitFor([&] {
      std::lock_guard<std::mutex> lock(mutex_);
      for (const auto& log : logs_)
        if (log.level >= rosgraph_msgs::Log::ERROR && log.msg.find(fragment) != std::string::npos) return true;
      return false;
    }, seconds);
  }

  /// A bad state is dropped (no output with its stamp), logged with `fragment`, counted once in /diagnostics
  /// under "dropped mesh_state: <reason>", and the node survives.
  void expectDroppedAndSurvived(const sensor_msgs::PointCloud2& bad, const std::string& fragment, const std::string& reason) {
    const std::string key = "dropped mesh_state: " + reason;
    const std::string before = nextDiagnosticValue(key);
    const std::string expected = std::to_string((before.empty() ? 0L : std::stol(before)) + 1);
    EXPECT_FALSE(roundTrip(bad, 1.0)) << "a bad state was published: " << fragment;
    EXPECT_TRUE(logged(fragment)) << "no error on /rosout containing '" << fragment << "'";
    EXPECT_TRUE(roundTrip(goodState())) << "the node did not recover after: " << fragment;
    EXPECT_EQ(diagnosticAfterChange(key, expected), expected) << "the drop was not counted under its reason: " << fragment;
  }

  /// After a change: `expected` once a /diagnostics status received after this call shows it for `key`, else
  /// the last value shown ("" if none came) within `seconds`. A status published before the change may still
  /// be on its way (seen once in a fresh-clone run: "stamp gain" 1 just after reconfiguring it to 0.5).
  std::string diagnosticAfterChange(const std::string& key, const std::string& expected, double seconds = 5.0) {
    std::string last;
    waitFor([&] {
      last = diagnosticValue(key, 1.0);
      return last == expected;
    }, seconds);
    return last;
  }

  /// The value of `key` in a /diagnostics status of the node received after this call, "" if none came.
  std::string diagnosticValue(const std::string& key, double seconds = 5.0) {
    return diagnosticAfterThisCall(key, seconds, true);
  }

  /// The value of `key` in the first /diagnostics status of the node received after this call, "" if that
  /// status has no such key (a count with nothing counted yet) or none came.
  std::string nextDiagnosticValue(const std::string& key, double seconds = 5.0) {
    return diagnosticAfterThisCall(key, seconds, false);
  }

  std::string diagnosticAfterThisCall(const std::string& key, double seconds, bool untilTheKeyShows) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      diagnostics_.clear();
    }
    std::string value;
    waitFor([&] {
      std::lock_guard<std::mutex> lock(mutex_);
      for (const auto& d : diagnostics_)
        for (const auto& kv : d.values)
          if (kv.key == key) value = kv.value;
      return !value.empty() || (!untilTheKeyShows && !diagnostics_.empty());
    }, seconds);
    return value;
  }

  void onDiagnostics(const diagnostic_msgs::DiagnosticArrayConstPtr& d) {
    std::lock_guard<std::mutex> lock(mutex_);
    for (const auto& status : d->status)
      if (status.name.find("enrichment") != std::string::npos) diagnostics_.push_back(status);
  }

  void onEnriched(const sensor_msgs::PointCloud2ConstPtr& m) { std::lock_guard<std::mutex> l(mutex_); enriched_.push_back(m); }
  void onStatus(const de::EnrichmentStatusConstPtr& m) { std::lock_guard<std::mutex> l(mutex_); statuses_.push_back(m); }
  void onLog(const rosgraph_msgs::Log& m) { std::lock_guard<std::mutex> l(mutex_); logs_.push_back(m); }

  ros::NodeHandle nh_;
  ros::Publisher restPub_, statePub_, contactsPub_, posePub_;
  ros::Subscriber enrichedSub_, statusSub_, logSub_, diagnosticsSub_;
  std::vector<diagnostic_msgs::DiagnosticStatus> diagnostics_;
  std::mutex mutex_;
  std::vector<sensor_msgs::PointCloud2ConstPtr> enriched_;
  std::vector<de::EnrichmentStatusConstPtr> statuses_;
  std::vector<rosgraph_msgs::Log> logs_;
  de::mesh::TriangleMesh rest_;
  uint32_t stampCounter_ = 0;
};

/// A one-example set made with the package's own pipeline on `rest`: a dent at the top centre, stamp 1 mm
/// inwards. Returns the dented state; writes the set to `directory`.
inline Eigen::Matrix3Xd makeDentExampleSet(const de::mesh::TriangleMesh& rest, const std::string& directory) {
  Eigen::Matrix3Xd dented = rest.vertices;
  for (Eigen::Index v = 0; v < dented.cols(); ++v)
    dented(2, v) -= 0.002 * std::exp(-dented.col(v).head<2>().squaredNorm() / (2 * 0.008 * 0.008)) * dented(2, v) / 0.02;
  de::enrichment::ContactEnricherOptions options;
  options.descriptors.window.scale = 0.006;
  options.stampRadius = 0.02;
  const de::enrichment::ContactEnricher describer(rest, options);
  de::enrichment::Contact contact;
  contact.point = Eigen::Vector3d(0, 0, 0.02);
  const auto description = describer.describe(dented, contact);
  de::examples::Example example;
  example.contact = description.p;
  example.frame = description.B;
  example.rho = description.rho;
  example.mu = description.mu;
  example.stamp = cv::Mat(64, 64, CV_32FC3, cv::Scalar(0.0f, 0.0f, -0.001f));
  example.stampRadius = 0.02;
  de::examples::ExampleSet set;
  set.metadata.scene = "rostest";
  set.metadata.material["window_scale_m"] = 0.006;
  set.examples.push_back(example);
  de::examples::saveExampleSet(set, directory);
  return dented;
}

}  // namespace enrichment_test
