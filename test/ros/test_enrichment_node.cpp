// Integration test of the enrichment node's ROS contract against a real master (run by rostest with the
// node as a separate process or as a nodelet): outputs, headers, frames, and every bad-input case is
// logged on /rosout and survived with the last good state kept.
#include <geometry_msgs/TransformStamped.h>

#include <filesystem>
#include <fstream>
#include <limits>
#include <set>

#include "deformation_enrichment/SegmentSites.h"
#include "enrichment_node_fixture.hpp"

namespace {

using de::ros_layer::cloudFromPositions;
using enrichment_test::EnrichmentNodeTest;
using enrichment_test::makeDentExampleSet;
using enrichment_test::slabSurface;
using enrichment_test::waitFor;

TEST_F(EnrichmentNodeTest, EnrichedStateKeepsStampFrameLayoutAndStatusFollows) {
  const sensor_msgs::PointCloud2 cloud = goodState();
  ASSERT_TRUE(roundTrip(cloud));
  const auto out = findEnriched(cloud.header.stamp);
  EXPECT_EQ(out->header.frame_id, "slab");
  EXPECT_EQ(out->width * out->height, cloud.width * cloud.height);
  EXPECT_EQ(out->fields.size(), cloud.fields.size());
  EXPECT_EQ(out->data, cloud.data) << "without contacts and examples the state passes unchanged";
  EXPECT_TRUE(waitFor([&] {
    std::lock_guard<std::mutex> lock(mutex_);
    for (const auto& s : statuses_)
      if (s->header.stamp == cloud.header.stamp && s->header.frame_id == "slab" && s->compute_ms >= 0.0f) return true;
    return false;
  }, 3.0));
}

TEST_F(EnrichmentNodeTest, HundredThousandVertexStateFlowsThrough) {
  setRest(slabSurface(223));
  ASSERT_GE(rest_.numVertices(), 100000);
  const sensor_msgs::PointCloud2 cloud = goodState();
  ASSERT_TRUE(roundTrip(cloud, 10.0));
  const auto out = findEnriched(cloud.header.stamp);
  EXPECT_EQ(out->header.frame_id, cloud.header.frame_id);
  EXPECT_EQ(out->width * out->height, rest_.numVertices());
  EXPECT_TRUE(de::ros_layer::positionsFromCloud(*out).allFinite());
}

// A burst of 10,000 states within about a second, far faster than they are enriched: the bounded queues
// drop the older ones, and /diagnostics counts every state either as received or as lost on the way (the
// transport numbers them), exactly; the node goes on enriching.
TEST_F(EnrichmentNodeTest, ABurstOfTenThousandStatesIsCountedAndSurvived) {
  const std::string inKey = "mesh states in", lostKey = "mesh states lost in the input queue (newer states came first)";
  const auto count = [&](const std::string& key) {
    const std::string value = diagnosticValue(key);
    return value.empty() ? -1L : std::stol(value);
  };
  const long inBefore = count(inKey), lostBefore = count(lostKey);
  ASSERT_GE(inBefore, 0);
  ASSERT_GE(lostBefore, 0);
  constexpr int kBurst = 10000;
  const ros::WallTime start = ros::WallTime::now();
  for (int i = 0; i < kBurst; ++i) {
    statePub_.publish(goodState());
    if (i % 100 == 99) ros::WallDuration(0.01).sleep();
  }
  RecordProperty("burst_seconds", std::to_string((ros::WallTime::now() - start).toSec()));
  ASSERT_TRUE(roundTrip(goodState(), 10.0)) << "the node did not enrich after the burst";
  // The diagnostics count up to the last state once a status after it is out.
  long in = 0, lost = 0;
  waitFor([&] {
    in = count(inKey) - inBefore;
    lost = count(lostKey) - lostBefore;
    return in + lost == kBurst + 1;
  }, 10.0);
  std::printf("burst of %d states: %ld received, %ld lost in the queues\n", kBurst, in, lost);
  EXPECT_EQ(in + lost, kBurst + 1);
  EXPECT_GT(lost, 0);
}

TEST_F(EnrichmentNodeTest, BadMeshStatesAreLoggedDroppedCountedByReasonAndSurvived) {
  Eigen::Matrix3Xf tooFew = rest_.vertices.cast<float>().leftCols(rest_.numVertices() - 1);
  expectDroppedAndSurvived(cloudFromPositions(tooFew, header()), "points, the rest mesh has",
                           "point count differs from the rest mesh");

  sensor_msgs::PointCloud2 noZ = goodState();
  noZ.fields.pop_back();  // x, y only
  expectDroppedAndSurvived(noZ, "has no 'z' field", "invalid point cloud");

  Eigen::Matrix3Xf withNaN = rest_.vertices.cast<float>();
  withNaN(1, 7) = std::numeric_limits<float>::quiet_NaN();
  expectDroppedAndSurvived(cloudFromPositions(withNaN, header()), "point 7 is not finite", "invalid mesh state");

  sensor_msgs::PointCloud2 truncated = goodState();
  truncated.data.resize(truncated.data.size() / 2);
  expectDroppedAndSurvived(truncated, "does not match", "invalid point cloud");
}

TEST_F(EnrichmentNodeTest, EmptyOrBrokenRestMeshIsRejectedAndTheOldOneKept) {
  pcl_msgs::PolygonMesh empty;
  empty.header = header();
  restPub_.publish(empty);
  EXPECT_TRUE(logged("rest_mesh"));
  EXPECT_TRUE(roundTrip(goodState())) << "states of the old rest mesh must still be enriched";

  pcl_msgs::PolygonMesh broken = de::ros_layer::messageFromTriangleMesh(rest_, header());
  broken.polygons[0].vertices[1] = 999999;
  restPub_.publish(broken);
  EXPECT_TRUE(logged("references vertex 999999"));
  EXPECT_TRUE(roundTrip(goodState()));
}

TEST_F(EnrichmentNodeTest, ContactsInUnknownFramesAreRejectedValidOnesReported) {
  de::ToolContactArray contacts;
  contacts.header = header();
  de::ToolContact contact;
  contact.tool_id = "PSM1";
  contact.in_contact = true;
  contact.position.z = 0.02;
  contact.normal.z = 1.0;
  contacts.contacts.push_back(contact);

  contacts.header.frame_id = "no_such_frame";
  contactsPub_.publish(contacts);
  EXPECT_TRUE(logged("cannot transform contact from frame 'no_such_frame'"));

  contacts.header = header();
  contacts.contacts[0].position.x = std::numeric_limits<double>::quiet_NaN();
  contactsPub_.publish(contacts);
  EXPECT_TRUE(logged("non-finite"));

  contacts.contacts[0].position.x = 0.0;
  contactsPub_.publish(contacts);
  ros::WallDuration(0.3).sleep();
  sensor_msgs::PointCloud2 state = goodState();
  state.header.stamp = contacts.header.stamp;
  ASSERT_TRUE(roundTrip(state));
  EXPECT_TRUE(waitFor([&] {
    std::lock_guard<std::mutex> lock(mutex_);
    for (const auto& s : statuses_)
      if (s->header.stamp == state.header.stamp && s->tool_ids == std::vector<std::string>{"PSM1"}) return true;
    return false;
  }, 3.0)) << "the valid contact did not reach the status";
}

TEST_F(EnrichmentNodeTest, ToolPoseNearTheSurfaceBecomesAContact) {
  expectToolPoseContact([&](const Eigen::Vector3d& p, const std_msgs::Header& h) {
    posePub_.publish(de::ros_layer::poseAt(p, h));
  });
}

TEST_F(EnrichmentNodeTest, ToolTransformOfOlderCrtkStacksBecomesAContact) {
  // dVRK <= 2.0 and AMBF before 2022 publish measured_cp as a TransformStamped.
  auto transformPub = nh_.advertise<geometry_msgs::TransformStamped>("tool_transform", 10);
  ASSERT_TRUE(waitFor([&] { return transformPub.getNumSubscribers() > 0; }, 5.0));
  expectToolPoseContact([&](const Eigen::Vector3d& p, const std_msgs::Header& h) {
    geometry_msgs::TransformStamped transform;
    transform.header = h;
    transform.child_frame_id = "PSM1_tool_tip";
    transform.transform.translation.x = p.x();
    transform.transform.translation.y = p.y();
    transform.transform.translation.z = p.z();
    transform.transform.rotation.w = 1.0;
    transformPub.publish(transform);
  });
  // A non-finite transform is dropped; the node keeps enriching.
  geometry_msgs::TransformStamped bad;
  bad.header = header();
  bad.transform.translation.x = std::numeric_limits<double>::quiet_NaN();
  bad.transform.rotation.w = 1.0;
  transformPub.publish(bad);
  ros::WallDuration(0.2).sleep();
  sensor_msgs::PointCloud2 after = goodState();
  ASSERT_TRUE(roundTrip(after)) << "the node must keep running after a NaN tool transform";
  EXPECT_TRUE(de::ros_layer::positionsFromCloud(*findEnriched(after.header.stamp)).allFinite());
}

TEST_F(EnrichmentNodeTest, MarkersForSubscribersAndDiagnostics) {
  visualization_msgs::MarkerArrayConstPtr markers;
  diagnostic_msgs::DiagnosticArrayConstPtr diagnostics;
  auto markerSub = nh_.subscribe<visualization_msgs::MarkerArray>(
      "enrichment/markers", 1, [&](const visualization_msgs::MarkerArrayConstPtr& m) { markers = m; });
  auto diagnosticsSub = nh_.subscribe<diagnostic_msgs::DiagnosticArray>(
      "/diagnostics", 10, [&](const diagnostic_msgs::DiagnosticArrayConstPtr& d) {
        for (const auto& status : d->status)
          if (status.name.find("enrichment") != std::string::npos) diagnostics = d;
      });
  ASSERT_TRUE(roundTrip(goodState()));
  ASSERT_TRUE(waitFor([&] { return markers != nullptr; }, 5.0)) << "no markers although subscribed";
  ASSERT_FALSE(markers->markers.empty());
  EXPECT_EQ(markers->markers[0].type, visualization_msgs::Marker::TRIANGLE_LIST);
  EXPECT_EQ(markers->markers[0].points.size(), 3u * rest_.numTriangles());
  EXPECT_EQ(markers->markers[0].header.frame_id, "slab");
  EXPECT_TRUE(waitFor([&] { return diagnostics != nullptr; }, 5.0)) << "no /diagnostics from the node";
}

// The test launch sets ~marker_fine_offset: the fine truth of a state (fine_state, its stamp or shortly
// before) is drawn beside it; one of another size or in another frame is not, is counted in /diagnostics,
// and the node goes on.
TEST_F(EnrichmentNodeTest, FineTruthOfTheDrawnStateBesideItAndAWrongSizedOneLeftOut) {
  std::mutex mutex;
  std::vector<visualization_msgs::MarkerArrayConstPtr> arrays;
  auto markerSub = nh_.subscribe<visualization_msgs::MarkerArray>("enrichment/markers", 4, [&](const visualization_msgs::MarkerArrayConstPtr& m) {
    std::lock_guard<std::mutex> lock(mutex);
    arrays.push_back(m);
  });
  ros::Publisher finePub = nh_.advertise<sensor_msgs::PointCloud2>("fine_state", 2);
  ASSERT_TRUE(waitFor([&] { return finePub.getNumSubscribers() > 0; }, 5.0)) << "the node does not listen to fine_state";
  auto drawnWith = [&](const ros::Time& stamp, bool fine) {
    return waitFor([&] {
      std::lock_guard<std::mutex> lock(mutex);
      for (const auto& array : arrays) {
        if (array->markers.empty() || array->markers[0].header.stamp != stamp) continue;
        const bool drawn = std::any_of(array->markers.begin(), array->markers.end(), [&](const visualization_msgs::Marker& m) {
          return m.ns == "fine_surface" && m.id == 0 && m.points.size() == 3u * static_cast<std::size_t>(rest_.numTriangles());
        });
        if (drawn == fine) return true;
      }
      return false;
    }, 5.0);
  };
  sensor_msgs::PointCloud2 state = goodState();
  Eigen::Matrix3Xf fine = rest_.vertices.cast<float>();
  fine.row(2).array() -= 0.001f;
  finePub.publish(cloudFromPositions(fine, state.header));
  ros::WallDuration(0.1).sleep();
  ASSERT_TRUE(roundTrip(state));
  EXPECT_TRUE(drawnWith(state.header.stamp, true)) << "the fine truth of the drawn state is not in the markers";
  sensor_msgs::PointCloud2 next = goodState();
  finePub.publish(cloudFromPositions(fine.leftCols(fine.cols() - 1), next.header));
  ros::WallDuration(0.1).sleep();
  ASSERT_TRUE(roundTrip(next));
  EXPECT_TRUE(drawnWith(next.header.stamp, false)) << "a fine state of another size must not be drawn";
  EXPECT_FALSE(diagnosticValue("dropped fine_state: point count differs from the mesh state").empty())
      << "the refused fine state must be counted in /diagnostics";
  sensor_msgs::PointCloud2 third = goodState();
  sensor_msgs::PointCloud2 elsewhere = cloudFromPositions(fine, third.header);
  elsewhere.header.frame_id = "another_frame";
  finePub.publish(elsewhere);
  ros::WallDuration(0.1).sleep();
  ASSERT_TRUE(roundTrip(third));
  EXPECT_TRUE(drawnWith(third.header.stamp, false)) << "a fine state in another frame must not be drawn";
  EXPECT_FALSE(diagnosticValue("dropped fine_state: frame differs from the mesh state's").empty());
  // A simulator that runs on its own stamps its states itself, the truth has its tool command's stamp: the
  // newest fine state at or before a state, within ~marker_fine_tolerance (0.1 s), is its truth.
  sensor_msgs::PointCloud2 fourth = goodState();
  std_msgs::Header commanded = fourth.header;
  commanded.stamp -= ros::Duration(0.05);
  finePub.publish(cloudFromPositions(fine, commanded));
  ros::WallDuration(0.1).sleep();
  ASSERT_TRUE(roundTrip(fourth));
  EXPECT_TRUE(drawnWith(fourth.header.stamp, true)) << "the truth commanded 50 ms before the state is not drawn";
  sensor_msgs::PointCloud2 fifth = goodState();
  for (const double offset : {-0.5, 0.02}) {
    commanded = fifth.header;
    commanded.stamp += ros::Duration(offset);
    finePub.publish(cloudFromPositions(fine, commanded));
  }
  ros::WallDuration(0.1).sleep();
  ASSERT_TRUE(roundTrip(fifth));
  EXPECT_TRUE(drawnWith(fifth.header.stamp, false)) << "a truth 0.5 s older or newer than the state must not be drawn";
  ASSERT_TRUE(roundTrip(goodState())) << "the node must keep running";
}

TEST_F(EnrichmentNodeTest, SegmentSitesLabelsEveryVertexSymmetricallyAndRejectsBadRequests) {
  ASSERT_TRUE(ros::service::waitForService("enrichment/segment_sites", 10000));
  de::SegmentSites call;
  call.request.regions = 3;
  ASSERT_TRUE(ros::service::call("enrichment/segment_sites", call));
  ASSERT_TRUE(call.response.success) << call.response.message;
  ASSERT_EQ(call.response.labels.size(), static_cast<size_t>(rest_.numVertices()));
  EXPECT_EQ(std::set<uint32_t>(call.response.labels.begin(), call.response.labels.end()).size(), 3u);
  // The slab's four top corners are congruent sites; the top centre is not a corner.
  auto vertexAt = [&](double x, double y, double z) {
    Eigen::Index best = 0;
    (rest_.vertices.colwise() - Eigen::Vector3d(x, y, z)).colwise().squaredNorm().minCoeff(&best);
    return call.response.labels[static_cast<size_t>(best)];
  };
  const uint32_t corner = vertexAt(0.05, 0.05, 0.02);
  EXPECT_EQ(vertexAt(-0.05, 0.05, 0.02), corner);
  EXPECT_EQ(vertexAt(-0.05, -0.05, 0.02), corner);
  EXPECT_EQ(vertexAt(0.05, -0.05, 0.02), corner);
  EXPECT_NE(vertexAt(0.0, 0.0, 0.02), corner);

  for (const uint32_t regions : {0u, 4000000000u, static_cast<uint32_t>(rest_.numVertices()) + 1}) {
    SCOPED_TRACE(regions);
    call.request.regions = regions;
    ASSERT_TRUE(ros::service::call("enrichment/segment_sites", call));
    EXPECT_FALSE(call.response.success);
    // The message names the request as sent (no wrap-around to a negative count) and the valid range.
    EXPECT_NE(call.response.message.find(std::to_string(regions)), std::string::npos) << call.response.message;
    EXPECT_NE(call.response.message.find("[1, " + std::to_string(rest_.numVertices()) + "]"), std::string::npos)
        << call.response.message;
  }
  EXPECT_TRUE(roundTrip(goodState())) << "the node must keep enriching after a failed segmentation";
}

TEST_F(EnrichmentNodeTest, ExampleSetEnrichesOnlyAtTheContactSurvivesACorruptSetAndFadesOnLiftOff) {
  setRest(slabSurface(20));
  const std::string good = ::testing::TempDir() + "de_rostest_set", bad = ::testing::TempDir() + "de_rostest_bad_set";
  const Eigen::Matrix3Xd dented = makeDentExampleSet(rest_, good);

  const de::LoadExampleSet::Response loaded = loadSet(good);
  ASSERT_TRUE(loaded.success) << loaded.message;
  EXPECT_EQ(loaded.num_examples, 1u);

  auto touchAndCheck = [&](const char* when) {
    const de::ToolContactArray contacts = touchTopCentre();
    sensor_msgs::PointCloud2 state = cloudFromPositions(dented.cast<float>(), contacts.header);
    ASSERT_TRUE(roundTrip(state)) << when;
    const Eigen::Matrix3Xf in = de::ros_layer::positionsFromCloud(state);
    const Eigen::Matrix3Xf out = de::ros_layer::positionsFromCloud(*findEnriched(state.header.stamp));
    ASSERT_TRUE(out.allFinite());
    int touched = 0;
    for (Eigen::Index v = 0; v < in.cols(); ++v) {
      if ((rest_.vertices.col(v) - Eigen::Vector3d(0, 0, 0.02)).norm() > 0.021) {
        EXPECT_EQ(std::memcmp(in.col(v).data(), out.col(v).data(), 3 * sizeof(float)), 0) << when << ": vertex " << v;
      } else if ((out.col(v) - in.col(v)).norm() > 0.0f) {
        ++touched;
      }
    }
    EXPECT_GT(touched, 0) << when << ": no detail at the contact";
    Eigen::Index centre = 0;
    (rest_.vertices.colwise() - Eigen::Vector3d(0, 0, 0.02)).colwise().squaredNorm().minCoeff(&centre);
    EXPECT_NEAR(out(2, centre) - in(2, centre), -0.001, 2e-4) << when << ": the stamp's 1 mm at the contact";
    EXPECT_TRUE(waitFor([&] {
      std::lock_guard<std::mutex> lock(mutex_);
      for (const auto& s : statuses_)
        if (s->header.stamp == state.header.stamp && s->vertices_touched > 0 && s->confidence > 0.5f &&
            s->example_ids == std::vector<uint32_t>{0})
          return true;
      return false;
    }, 3.0)) << when << ": status without the example";
  };
  touchAndCheck("first set");

  std::filesystem::create_directories(bad);
  std::ofstream(bad + "/manifest.json") << "{ not json";
  const de::LoadExampleSet::Response refused = loadSet(bad);
  EXPECT_FALSE(refused.success);
  EXPECT_EQ(refused.num_examples, 1u) << "the old set must stay active";
  touchAndCheck("after a corrupt set");

  // Lift-off with the tissue still dented: the released site keeps its detail ...
  de::ToolContactArray lifted;
  lifted.header = header();
  contactsPub_.publish(lifted);
  ros::WallDuration(0.3).sleep();
  sensor_msgs::PointCloud2 state = cloudFromPositions(dented.cast<float>(), lifted.header);
  ASSERT_TRUE(roundTrip(state));
  const Eigen::Matrix3Xf in = de::ros_layer::positionsFromCloud(state);
  const Eigen::Matrix3Xf out = de::ros_layer::positionsFromCloud(*findEnriched(state.header.stamp));
  Eigen::Index centre = 0;
  (rest_.vertices.colwise() - Eigen::Vector3d(0, 0, 0.02)).colwise().squaredNorm().minCoeff(&centre);
  EXPECT_NEAR(out(2, centre) - in(2, centre), -0.001, 2e-4) << "the released tissue keeps its detail";
  EXPECT_TRUE(out.allFinite());
  EXPECT_TRUE(waitFor([&] {
    std::lock_guard<std::mutex> lock(mutex_);
    for (const auto& s : statuses_)
      if (s->header.stamp == state.header.stamp && s->released_sites == 1u && s->tool_ids.empty()) return true;
    return false;
  }, 3.0)) << "status without the released site";
  // ... and back at rest nothing is left.
  sensor_msgs::PointCloud2 atRest = cloudFromPositions(rest_.vertices.cast<float>(), header());
  ASSERT_TRUE(roundTrip(atRest));
  EXPECT_EQ(findEnriched(atRest.header.stamp)->data, atRest.data) << "detail must vanish once the tissue is at rest";
  sensor_msgs::PointCloud2 later = cloudFromPositions(rest_.vertices.cast<float>(), header());
  ASSERT_TRUE(roundTrip(later));
  EXPECT_EQ(findEnriched(later.header.stamp)->data, later.data);
}

TEST_F(EnrichmentNodeTest, TwoToolsWithOverlappingStampsGiveAContinuousSurface) {
  setRest(slabSurface(40));  // 2.5 mm grid on the top
  const std::string directory = ::testing::TempDir() + "de_rostest_two_tools_set";
  const Eigen::Matrix3Xd dented = makeDentExampleSet(rest_, directory);
  const de::LoadExampleSet::Response loaded = loadSet(directory);
  ASSERT_TRUE(loaded.success) << loaded.message;

  // Largest change of the added displacement along a mesh edge, for the given tool positions.
  auto enrichWith = [&](const std::vector<double>& xs, Eigen::Matrix3Xf& added) {
    de::ToolContactArray contacts;
    contacts.header = header();
    for (size_t i = 0; i < xs.size(); ++i) {
      de::ToolContact tool;
      tool.tool_id = "PSM" + std::to_string(i + 1);
      tool.in_contact = true;
      tool.position.x = xs[i];
      tool.position.z = 0.019;
      tool.normal.z = 1.0;
      contacts.contacts.push_back(tool);
    }
    contactsPub_.publish(contacts);
    ros::WallDuration(0.3).sleep();
    const sensor_msgs::PointCloud2 state = cloudFromPositions(dented.cast<float>(), contacts.header);
    if (!roundTrip(state)) return -1.0f;
    added = de::ros_layer::positionsFromCloud(*findEnriched(state.header.stamp)) - de::ros_layer::positionsFromCloud(state);
    float largestJump = 0.0f;
    for (Eigen::Index t = 0; t < rest_.numTriangles(); ++t)
      for (int k = 0; k < 3; ++k)
        largestJump = std::max(largestJump, (added.col(rest_.triangles(k, t)) - added.col(rest_.triangles((k + 1) % 3, t))).norm());
    return largestJump;
  };
  Eigen::Matrix3Xf oneTool, twoTools;
  const float jumpOne = enrichWith({-0.0075}, oneTool);
  // Two tools 1.5 cm apart: their 2 cm stamps overlap over the middle.
  const float jumpTwo = enrichWith({-0.0075, 0.0075}, twoTools);
  ASSERT_GT(jumpOne, 0.0f);
  ASSERT_TRUE(twoTools.allFinite());
  EXPECT_GT(twoTools.colwise().norm().maxCoeff(), 5e-4f) << "no detail was added";
  EXPECT_LT(twoTools.colwise().norm().maxCoeff(), 1.3e-3f) << "overlapping stamps were added up";
  // A seam where the stamps overlap would make the two-tool surface rougher than one stamp's own rim.
  EXPECT_LE(jumpTwo, 1.1f * jumpOne) << "a seam between the two stamps";
}

}  // namespace

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_enrichment_node");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}

// The tool pose stream stalls for 5 s while the states go on (stamped at 60 Hz): the tool stays in contact
// for ~contact_timeout (0.5 s) after its last pose, then counts as lifted and the release rules apply (the
// still dented site keeps its detail, released); when poses come again, the tool is back in contact.
TEST_F(EnrichmentNodeTest, AToolPoseStreamThatStallsTimesOutAndComesBack) {
  setRest(slabSurface(20));
  const Eigen::Matrix3Xd dented = makeDentExampleSet(rest_, ::testing::TempDir() + "de_rostest_stall_set");
  const de::LoadExampleSet::Response loaded = loadSet(::testing::TempDir() + "de_rostest_stall_set");
  ASSERT_TRUE(loaded.success) << loaded.message;

  const ros::Time base = header().stamp;
  stampCounter_ += 10;  // later tests' stamps come after this test's 5 s
  const auto pose = [&](const ros::Time& stamp) {
    geometry_msgs::PoseStamped p;
    p.header.frame_id = "slab";
    p.header.stamp = stamp;
    p.pose.position.z = 0.0185;  // half a millimetre above the dent's floor
    p.pose.orientation.w = 1.0;
    posePub_.publish(p);
    ros::WallDuration(0.2).sleep();
  };
  // The state stamped `seconds` after the last pose: the tools in contact and the detail at the contact.
  const auto state = [&](double seconds) {
    sensor_msgs::PointCloud2 cloud = cloudFromPositions(dented.cast<float>(), header());
    cloud.header.stamp = base + ros::Duration(seconds);
    EXPECT_TRUE(roundTrip(cloud)) << "no output " << seconds << " s into the stall";
    const de::EnrichmentStatusConstPtr status = statusFor(cloud.header.stamp);
    const sensor_msgs::PointCloud2ConstPtr out = findEnriched(cloud.header.stamp);
    const Eigen::Matrix3Xf in = de::ros_layer::positionsFromCloud(cloud);
    const Eigen::Matrix3Xf enriched = out ? de::ros_layer::positionsFromCloud(*out) : in;
    EXPECT_TRUE(enriched.allFinite());
    return std::make_pair(status, (enriched - in).colwise().norm().maxCoeff());
  };
  pose(base);
  int inContact = 0, lifted = 0;
  for (int frame = 1; frame <= 300; ++frame) {
    const double seconds = frame / 60.0;
    const auto [status, detail] = state(seconds);
    if (!status) continue;
    const bool touching = status->tool_ids == std::vector<std::string>{"tool_pose"};
    if (seconds < 0.45) inContact += touching;
    if (seconds > 0.55) {
      lifted += !touching && status->released_sites == 1u;
      EXPECT_GT(detail, 5e-4f) << "the released, still dented site lost its detail " << seconds << " s into the stall";
    }
  }
  EXPECT_EQ(inContact, 26) << "states within the contact timeout that kept the tool";
  EXPECT_EQ(lifted, 300 - 33) << "states after the timeout with the tool lifted and its site released";
  pose(base + ros::Duration(5.1));
  const auto [status, detail] = state(5.1 + 1.0 / 60.0);
  ASSERT_TRUE(status);
  EXPECT_EQ(status->tool_ids, std::vector<std::string>{"tool_pose"}) << "the tool is not back in contact";
  EXPECT_GT(detail, 5e-4f);
}

// The coarse simulator restarts while a released site still holds detail: it publishes its rest mesh again
// and its states resume. Nothing of the old run is applied to the new one: the first states, dented or not,
// come out as they went in until a tool touches.
TEST_F(EnrichmentNodeTest, ASimulatorRestartLeavesNoStaleDetail) {
  setRest(slabSurface(20));
  const Eigen::Matrix3Xd dented = makeDentExampleSet(rest_, ::testing::TempDir() + "de_rostest_restart_set");
  const de::LoadExampleSet::Response loaded = loadSet(::testing::TempDir() + "de_rostest_restart_set");
  ASSERT_TRUE(loaded.success) << loaded.message;
  // Touched, then released with the tissue still dented: the released site keeps its detail.
  sensor_msgs::PointCloud2 touched = cloudFromPositions(dented.cast<float>(), touchTopCentre().header);
  ASSERT_TRUE(roundTrip(touched));
  ASSERT_NE(findEnriched(touched.header.stamp)->data, touched.data) << "no detail before the restart";
  contactsPub_.publish(de::ToolContactArray());
  ros::WallDuration(0.3).sleep();
  sensor_msgs::PointCloud2 released = cloudFromPositions(dented.cast<float>(), header());
  ASSERT_TRUE(roundTrip(released));
  ASSERT_NE(findEnriched(released.header.stamp)->data, released.data) << "the released site lost its detail";

  // The restarted simulator's rest mesh: the surface 2 mm higher (another surface of the same size), then
  // its states, dented from the first: none at rest in between, which would release the old site by itself.
  const std::string builtKey = "rest surfaces built";
  const long builtBefore = std::stol(diagnosticValue(builtKey));
  de::mesh::TriangleMesh raised = rest_;
  raised.vertices.row(2).array() += 0.002;
  Eigen::Matrix3Xd raisedDent = dented;
  raisedDent.row(2).array() += 0.002;
  restPub_.publish(de::ros_layer::messageFromTriangleMesh(raised, header()));
  ros::WallDuration(0.3).sleep();
  ASSERT_TRUE(waitFor([&] {
    EXPECT_TRUE(roundTrip(cloudFromPositions(raisedDent.cast<float>(), header())));
    return std::stol(diagnosticValue(builtKey)) > builtBefore;
  }, 20.0)) << "the new rest mesh was never built";
  for (int frame = 0; frame < 5; ++frame) {
    sensor_msgs::PointCloud2 state = cloudFromPositions(raisedDent.cast<float>(), header());
    ASSERT_TRUE(roundTrip(state));
    EXPECT_EQ(findEnriched(state.header.stamp)->data, state.data) << "detail of the old run on state " << frame << " of the new";
    const de::EnrichmentStatusConstPtr status = statusFor(state.header.stamp);
    ASSERT_TRUE(status);
    EXPECT_EQ(status->released_sites, 0u);
  }
}
