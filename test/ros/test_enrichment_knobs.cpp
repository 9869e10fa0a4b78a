// Integration test of the enrichment node's run-time knobs against a real master (rostest, node process or
// nodelet): dynamic_reconfigure of stamp gain, kernel widths and Hermite order, reuse of an unchanged
// input, a rest mesh replaced at run time (a cut), and the tool tip geometry from robot_description
// (its geometry without a node: test/unit/enrichment/test_tool_tip.cpp).
#include <dynamic_reconfigure/Reconfigure.h>

#include <map>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/tet_mesh.hpp"
#include "deformation_enrichment/enrichment/tool_tip.hpp"
#include "enrichment_node_fixture.hpp"

namespace {

using de::ros_layer::cloudFromPositions;
using de::ros_layer::positionsFromCloud;
using enrichment_test::makeDentExampleSet;
using enrichment_test::slabSurface;
using enrichment_test::waitFor;

class EnrichmentKnobsTest : public enrichment_test::EnrichmentNodeTest {
protected:
  void TearDown() override {  // one node serves every test: leave the knobs at their defaults
    reconfigure({{"stamp_gain", 1.0}, {"sigma_rho", 0.0}, {"sigma_u", 0.0}, {"max_weight_norm", 4.0}}, {{"hermite_order", 0}},
                {{"blend", "regression"}});
  }

  /// Calls ~set_parameters; returns the configuration the node reports back.
  dynamic_reconfigure::Config reconfigure(const std::map<std::string, double>& doubles,
                                          const std::map<std::string, int>& ints = {},
                                          const std::map<std::string, std::string>& strings = {}) {
    dynamic_reconfigure::Reconfigure call;
    for (const auto& [name, value] : doubles) {
      dynamic_reconfigure::DoubleParameter p;
      p.name = name;
      p.value = value;
      call.request.config.doubles.push_back(p);
    }
    for (const auto& [name, value] : ints) {
      dynamic_reconfigure::IntParameter p;
      p.name = name;
      p.value = value;
      call.request.config.ints.push_back(p);
    }
    for (const auto& [name, value] : strings) {
      dynamic_reconfigure::StrParameter p;
      p.name = name;
      p.value = value;
      call.request.config.strs.push_back(p);
    }
    EXPECT_TRUE(ros::service::waitForService("enrichment/set_parameters", 10000));
    EXPECT_TRUE(ros::service::call("enrichment/set_parameters", call));
    return call.response.config;
  }

  static int intIn(const dynamic_reconfigure::Config& config, const std::string& name) {
    for (const auto& p : config.ints)
      if (p.name == name) return p.value;
    return -1;
  }

  static std::string stringIn(const dynamic_reconfigure::Config& config, const std::string& name) {
    for (const auto& p : config.strs)
      if (p.name == name) return p.value;
    return {};
  }


  /// Publishes a contact at (x, 0, z) and returns its stamp once the node has it (states stamped up to
  /// 0.5 s later see it).
  ros::Time touch(double x, double z) {
    de::ToolContactArray contacts;
    contacts.header = header();
    de::ToolContact tool;
    tool.tool_id = "PSM1";
    tool.in_contact = true;
    tool.position.x = x;
    tool.position.z = z;
    tool.normal.z = 1.0;
    contacts.contacts.push_back(tool);
    contactsPub_.publish(contacts);
    // Under load the contact may arrive after a state sent right away: probe with rest states (stamped just
    // after the contact) until one reports the tool.
    for (int k = 1; k <= 40; ++k) {
      sensor_msgs::PointCloud2 probe = goodState();
      probe.header.stamp = contacts.header.stamp + ros::Duration(0.001 * k);
      if (roundTrip(probe, 1.0)) {
        const auto status = statusFor(probe.header.stamp, 1.0);
        if (status && !status->tool_ids.empty()) break;
      }
      ros::WallDuration(0.05).sleep();
    }
    return contacts.header.stamp;
  }

  /// Sends `positions` stamped `base + offset` and returns the added displacement (output - input).
  Eigen::Matrix3Xf addedAt(const Eigen::Matrix3Xd& positions, const ros::Time& base, double offset = 0.0) {
    std_msgs::Header h;
    h.frame_id = "slab";
    h.stamp = base + ros::Duration(offset);
    const sensor_msgs::PointCloud2 state = cloudFromPositions(positions.cast<float>(), h);
    if (!roundTrip(state)) return Eigen::Matrix3Xf();
    lastStamp_ = h.stamp;
    return positionsFromCloud(*findEnriched(h.stamp)) - positionsFromCloud(state);
  }

  void loadSet(const std::string& directory) {
    de::LoadExampleSet load;
    load.request.path = directory;
    ASSERT_TRUE(ros::service::waitForService("enrichment/load_example_set", 10000));
    ASSERT_TRUE(ros::service::call("enrichment/load_example_set", load));
    ASSERT_TRUE(load.response.success) << load.response.message;
  }

  Eigen::Index vertexNear(const Eigen::Vector3d& p) const {
    Eigen::Index best = 0;
    (rest_.vertices.colwise() - p).colwise().squaredNorm().minCoeff(&best);
    return best;
  }


  ros::Time lastStamp_;
};

// What de_evaluate scores with flags is a start-up parameter of the node; /diagnostics shows the values in
// use (the nodelet's launch file sets three of them away from config/enrichment.yaml's) and the values refused
// (the node's launch file gives two of the wrong type, which roscpp's param() would ignore silently).
TEST_F(EnrichmentKnobsTest, StartUpBlendParametersAreInUse) {
  ros::NodeHandle privateNh("~");
  const std::string rimBand = privateNh.param<std::string>("expect_rim_band", "0.1");
  const std::string lambda = privateNh.param<std::string>("expect_rbf_lambda", "0.001");
  const std::string queueSize = privateNh.param<std::string>("expect_state_queue_size", "6");
  const std::string refused = privateNh.param<std::string>("expect_refused_parameters", "none");
  EXPECT_EQ(diagnosticAfterChange("parameters refused at start-up (defaults used)", refused), refused);
  EXPECT_EQ(diagnosticAfterChange("rim band", rimBand), rimBand);
  EXPECT_EQ(diagnosticAfterChange("rbf lambda", lambda), lambda);
  EXPECT_EQ(diagnosticAfterChange("mesh state queue size", queueSize), queueSize);
  EXPECT_EQ(diagnosticAfterChange("magnitude aware", "true"), "true");
  EXPECT_EQ(diagnosticAfterChange("cross-validated gain", "true"), "true");
  // The first test: no reconfiguration has run yet, so this is the start-up value (the node's: refused -2).
  EXPECT_EQ(diagnosticAfterChange("max weight norm (0 = no bound)", "4"), "4");
}

TEST_F(EnrichmentKnobsTest, StampGainScalesTheAddedDisplacementFromTheNextState) {
  setRest(slabSurface(20));
  const std::string directory = ::testing::TempDir() + "de_knobs_gain_set";
  const Eigen::Matrix3Xd dented = makeDentExampleSet(rest_, directory);
  loadSet(directory);

  const ros::Time contact = touch(0.0, 0.018);
  const Eigen::Matrix3Xf full = addedAt(dented, contact);
  ASSERT_GT(full.cols(), 0);
  const Eigen::Index centre = vertexNear(Eigen::Vector3d(0, 0, 0.02));
  EXPECT_NEAR(full(2, centre), -0.001, 2e-4) << "the stamp's 1 mm at gain 1";

  reconfigure({{"stamp_gain", 0.5}});
  EXPECT_EQ(diagnosticAfterChange("stamp gain", "0.5"), "0.5");
  const Eigen::Matrix3Xf half = addedAt(dented, contact, 0.1);  // same inputs: must not reuse the gain-1 result
  ASSERT_EQ(half.cols(), full.cols());
  EXPECT_NEAR(half(2, centre), 0.5f * full(2, centre), 1e-6f);
  EXPECT_LT((half - 0.5f * full).cwiseAbs().maxCoeff(), 1e-6f) << "the gain must scale every added displacement";

  reconfigure({{"stamp_gain", 0.0}});
  const Eigen::Matrix3Xf none = addedAt(dented, contact, 0.2);
  ASSERT_EQ(none.cols(), full.cols());
  EXPECT_EQ(none.cwiseAbs().maxCoeff(), 0.0f) << "gain 0 adds nothing";

  EXPECT_EQ(diagnosticValue("max weight norm (0 = no bound)"), "4");
  reconfigure({{"max_weight_norm", 2.5}});
  EXPECT_EQ(diagnosticAfterChange("max weight norm (0 = no bound)", "2.5"), "2.5");
  EXPECT_EQ(diagnosticValue("min confidence"), "0");
}

TEST_F(EnrichmentKnobsTest, KernelWidthsChangeTheConfidenceAndZeroRestoresTheLoadedWidths) {
  setRest(slabSurface(20));
  const std::string directory = ::testing::TempDir() + "de_knobs_width_set";
  const Eigen::Matrix3Xd dented = makeDentExampleSet(rest_, directory);
  loadSet(directory);
  // Off the dent's centre the deformation differs from the example's: a confidence below 1.
  const ros::Time contact = touch(0.008, 0.019);
  auto confidence = [&](double offset) {
    if (addedAt(dented, contact, offset).cols() == 0) return -1.0f;
    const auto status = statusFor(lastStamp_);
    return status ? status->confidence : -1.0f;
  };
  const float loaded = confidence(0.0);
  ASSERT_TRUE(std::isfinite(loaded));
  ASSERT_GT(loaded, 0.0f);
  ASSERT_LT(loaded, 0.999f) << "the test needs a contact whose descriptors differ from the example's";

  reconfigure({{"sigma_rho", 0.0}, {"sigma_u", 0.02}});
  EXPECT_EQ(diagnosticAfterChange("sigma_u", "0.02"), "0.02");
  const float narrow = confidence(0.1);
  EXPECT_TRUE(std::isfinite(narrow));
  EXPECT_LT(narrow, loaded) << "a narrower sigma_u must lower the eq. (15) weight of a dissimilar example";
  EXPECT_GE(narrow, 0.0f);

  reconfigure({{"sigma_u", 5.0}});
  const float wide = confidence(0.2);
  EXPECT_GT(wide, loaded) << "a wider sigma_u must raise it";
  EXPECT_LE(wide, 1.0f);

  reconfigure({{"sigma_rho", 0.0}, {"sigma_u", -1.0}});  // back to the widths the set was loaded with
  EXPECT_FLOAT_EQ(confidence(0.3), loaded);
}

TEST_F(EnrichmentKnobsTest, LowerHermiteOrderTruncatesHigherIsRefusedKeepingTheOldOne) {
  setRest(slabSurface(20));
  const std::string directory = ::testing::TempDir() + "de_knobs_order_set";
  const Eigen::Matrix3Xd dented = makeDentExampleSet(rest_, directory);  // mu orders 1..2
  loadSet(directory);
  EXPECT_EQ(diagnosticAfterChange("hermite order", "2"), "2");

  dynamic_reconfigure::Config reply = reconfigure({}, {{"hermite_order", 1}});
  EXPECT_EQ(intIn(reply, "hermite_order"), 1);
  EXPECT_TRUE(waitFor([&] { return diagnosticValue("hermite order", 1.0) == "1"; }, 10.0));
  const ros::Time contact = touch(0.0, 0.018);
  const Eigen::Matrix3Xf added = addedAt(dented, contact);
  ASSERT_GT(added.cols(), 0);
  EXPECT_TRUE(added.allFinite());
  EXPECT_NEAR(added(2, vertexNear(Eigen::Vector3d(0, 0, 0.02))), -0.001, 2e-4) << "order 1 still matches the example";

  reply = reconfigure({}, {{"hermite_order", 3}});
  EXPECT_EQ(intIn(reply, "hermite_order"), 1) << "an order above the set's must be refused, keeping the old one";
  EXPECT_TRUE(logged("hermite_order 3 refused"));
  EXPECT_EQ(diagnosticValue("hermite order"), "1");
  EXPECT_GT(addedAt(dented, contact, 0.1).cols(), 0) << "the node keeps enriching after a refused order";
}

TEST_F(EnrichmentKnobsTest, AnUnknownBlendIsRefusedKeepingTheBlendInUse) {
  setRest(slabSurface(20));
  const std::string directory = ::testing::TempDir() + "de_knobs_blend_set";
  const Eigen::Matrix3Xd dented = makeDentExampleSet(rest_, directory);
  loadSet(directory);

  dynamic_reconfigure::Config reply = reconfigure({}, {}, {{"blend", "paper"}});
  EXPECT_EQ(stringIn(reply, "blend"), "paper");
  EXPECT_EQ(diagnosticAfterChange("blend requested", "paper"), "paper");

  reply = reconfigure({}, {}, {{"blend", "nearest"}});
  EXPECT_EQ(stringIn(reply, "blend"), "paper") << "a blend that does not exist must be refused, keeping the old one";
  EXPECT_TRUE(logged("blend 'nearest' does not exist"));
  EXPECT_EQ(diagnosticValue("blend requested"), "paper");
  const ros::Time contact = touch(0.0, 0.018);
  const Eigen::Matrix3Xf added = addedAt(dented, contact);
  ASSERT_GT(added.cols(), 0) << "the node keeps enriching after a refused blend";
  EXPECT_TRUE(added.allFinite());
}

TEST_F(EnrichmentKnobsTest, UnchangedInputIsRepublishedWithoutRecomputingAChangedOneRecomputes) {
  setRest(slabSurface(20));
  const std::string directory = ::testing::TempDir() + "de_knobs_reuse_set";
  Eigen::Matrix3Xd dented = makeDentExampleSet(rest_, directory);
  loadSet(directory);
  const ros::Time contact = touch(0.0, 0.018);

  const Eigen::Matrix3Xf first = addedAt(dented, contact, 0.0);
  const auto firstStatus = statusFor(lastStamp_);
  const sensor_msgs::PointCloud2ConstPtr firstOut = findEnriched(lastStamp_);
  ASSERT_TRUE(firstStatus && firstOut);
  EXPECT_FALSE(firstStatus->reused);
  ASSERT_GT(firstStatus->vertices_touched, 0u);

  const Eigen::Matrix3Xf second = addedAt(dented, contact, 0.1);
  const auto secondStatus = statusFor(lastStamp_);
  const sensor_msgs::PointCloud2ConstPtr secondOut = findEnriched(lastStamp_);
  ASSERT_TRUE(secondStatus && secondOut);
  EXPECT_TRUE(secondStatus->reused) << "identical inputs must not be enriched again";
  EXPECT_EQ(secondStatus->states_reused, firstStatus->states_reused + 1);
  EXPECT_EQ(secondOut->data, firstOut->data) << "the republished state must be identical";
  EXPECT_EQ(secondOut->header.stamp, lastStamp_) << "with the new state's stamp";
  EXPECT_EQ(secondStatus->vertices_touched, firstStatus->vertices_touched);
  EXPECT_EQ(secondStatus->example_ids, firstStatus->example_ids);
  EXPECT_EQ(secondStatus->tool_ids, firstStatus->tool_ids);
  std::printf("[ reuse    ] enrich %.3f ms, republish unchanged %.3f ms (%zu-point state)\n", firstStatus->compute_ms,
              secondStatus->compute_ms, static_cast<size_t>(rest_.numVertices()));

  dented(2, vertexNear(Eigen::Vector3d(0, 0, 0.02))) -= 1e-4;  // a changed state
  const Eigen::Matrix3Xf third = addedAt(dented, contact, 0.2);
  const auto thirdStatus = statusFor(lastStamp_);
  ASSERT_TRUE(thirdStatus);
  EXPECT_FALSE(thirdStatus->reused) << "a changed state must be enriched afresh";
  EXPECT_EQ(thirdStatus->states_reused, secondStatus->states_reused);
  EXPECT_EQ(diagnosticValue("states reused (unchanged input)"), std::to_string(thirdStatus->states_reused));
}

TEST_F(EnrichmentKnobsTest, ReconfiguringWhileStatesStreamGivesOnlyConsistentOutputs) {
  setRest(slabSurface(20));
  const std::string directory = ::testing::TempDir() + "de_knobs_stream_set";
  const Eigen::Matrix3Xd dented = makeDentExampleSet(rest_, directory);
  loadSet(directory);
  const ros::Time contact = touch(0.0, 0.018);
  const Eigen::Index centre = vertexNear(Eigen::Vector3d(0, 0, 0.02));
  const float z = static_cast<float>(dented(2, centre));
  // States stream while the gain (1 <-> 0.5) and the Hermite order (2 <-> 1) change on the service thread:
  // every output must come from one consistent configuration (centre moved by 1 mm x gain), none torn.
  std::vector<ros::Time> stamps;
  for (int k = 0; k < 60; ++k) {
    std_msgs::Header h;
    h.frame_id = "slab";
    h.stamp = contact + ros::Duration(0.1 + 0.005 * k);
    statePub_.publish(cloudFromPositions(dented.cast<float>(), h));
    stamps.push_back(h.stamp);
    if (k % 10 == 5) reconfigure({{"stamp_gain", k % 20 == 5 ? 0.5 : 1.0}}, {{"hermite_order", k % 20 == 5 ? 1 : 0}});
    ros::spinOnce();
    ros::WallDuration(0.002).sleep();
  }
  waitFor([&] { return findEnriched(stamps.back()) != nullptr; }, 3.0);
  int outputs = 0;
  for (const ros::Time& stamp : stamps) {
    const auto out = findEnriched(stamp);
    if (!out) continue;  // the node's bounded input queue drops states under a burst
    ++outputs;
    const Eigen::Matrix3Xf positions = positionsFromCloud(*out);
    ASSERT_TRUE(positions.allFinite());
    const float moved = positions(2, centre) - z;
    EXPECT_TRUE(std::abs(moved + 0.001f) < 2e-4f || std::abs(moved + 0.0005f) < 1e-4f) << "centre moved " << moved;
    const auto status = statusFor(stamp, 1.0);
    ASSERT_TRUE(status);
    EXPECT_TRUE(std::isfinite(status->confidence));
  }
  EXPECT_GE(outputs, 5) << "the node must keep publishing while being reconfigured";
  std::printf("[ stream   ] %d of %zu states published during 6 reconfigurations\n", outputs, stamps.size());
}

/// The slab with a 5 mm wide, 10 mm deep groove cut across its top at x in [0.025, 0.03]: a different
/// closed surface (different vertex count) of the same object after a cut.
de::mesh::TriangleMesh cutSlabSurface() {
  const de::mesh::TetMesh slab =
      de::mesh::gridTetMesh(Eigen::Vector3d(-0.05, -0.05, 0), Eigen::Vector3d(0.05, 0.05, 0.02), Eigen::Vector3i(20, 20, 2));
  std::vector<int> kept;
  for (Eigen::Index t = 0; t < slab.tets.cols(); ++t) {
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (int k = 0; k < 4; ++k) centroid += slab.vertices.col(slab.tets(k, t)) / 4.0;
    if (!(centroid.x() > 0.025 && centroid.x() < 0.03 && centroid.z() > 0.01)) kept.push_back(static_cast<int>(t));
  }
  de::mesh::TetMesh cut;
  cut.vertices = slab.vertices;
  cut.tets.resize(4, static_cast<Eigen::Index>(kept.size()));
  for (size_t i = 0; i < kept.size(); ++i) cut.tets.col(static_cast<Eigen::Index>(i)) = slab.tets.col(kept[i]);
  return de::mesh::extractSurface(cut).surface;
}

TEST_F(EnrichmentKnobsTest, RestMeshReplacedAtRunTimeKeepsEnrichingAndRejectsOldSizedStates) {
  setRest(slabSurface(20));
  const std::string directory = ::testing::TempDir() + "de_knobs_cut_set";
  const Eigen::Matrix3Xd dentedA = makeDentExampleSet(rest_, directory);
  loadSet(directory);
  const ros::Time contactA = touch(0.0, 0.018);
  const Eigen::Matrix3Xf addedA = addedAt(dentedA, contactA);
  ASSERT_GT(addedA.cols(), 0);
  EXPECT_NEAR(addedA(2, vertexNear(Eigen::Vector3d(0, 0, 0.02))), -0.001, 2e-4) << "mesh A";
  const Eigen::Index verticesA = rest_.numVertices();

  setRest(cutSlabSurface());  // waits until a state of B's size goes through
  ASSERT_NE(rest_.numVertices(), verticesA) << "the cut must change the vertex count";
  Eigen::Matrix3Xd dentedB = rest_.vertices;
  for (Eigen::Index v = 0; v < dentedB.cols(); ++v)  // the dent of makeDentExampleSet, on B
    dentedB(2, v) -= 0.002 * std::exp(-dentedB.col(v).head<2>().squaredNorm() / (2 * 0.008 * 0.008)) * dentedB(2, v) / 0.02;
  const ros::Time contactB = touch(0.0, 0.018);
  const Eigen::Matrix3Xf addedB = addedAt(dentedB, contactB);
  ASSERT_EQ(addedB.cols(), rest_.numVertices());
  EXPECT_NEAR(addedB(2, vertexNear(Eigen::Vector3d(0, 0, 0.02))), -0.001, 2e-4) << "mesh B enriched at the contact";
  for (Eigen::Index v = 0; v < addedB.cols(); ++v) {
    if ((rest_.vertices.col(v) - Eigen::Vector3d(0, 0, 0.02)).norm() > 0.021) {
      ASSERT_EQ(addedB.col(v).norm(), 0.0f) << "vertex " << v << " outside the stamp";
    }
  }

  std_msgs::Header h = header();
  h.stamp = contactB + ros::Duration(0.1);
  EXPECT_FALSE(roundTrip(cloudFromPositions(dentedA.cast<float>(), h), 1.0)) << "a state of mesh A's size";
  EXPECT_TRUE(logged(std::to_string(verticesA) + " points, the rest mesh has " + std::to_string(rest_.numVertices())));
  EXPECT_GT(addedAt(dentedB, contactB, 0.2).cols(), 0) << "B keeps enriching after the rejected state";
}

TEST_F(EnrichmentKnobsTest, AnOpenRestMeshIsEnrichedFromAShellUnderIt) {
  setRest(slabSurface(20));
  const std::string directory = ::testing::TempDir() + "de_knobs_open_set";
  const Eigen::Matrix3Xd dented = makeDentExampleSet(rest_, directory);
  loadSet(directory);
  const de::mesh::TriangleMesh closed = rest_;
  const Eigen::Matrix3Xf closedAdded = addedAt(dented, touch(0.0, 0.018));
  ASSERT_GT(closedAdded.cols(), 0);
  // Triangles removed from the top (a hole, not a groove): the surface has no interior, so without a volume
  // the site density is a shell under it (~shell_thickness, three window scales by default).
  de::mesh::TriangleMesh open = closed;
  std::vector<Eigen::Index> kept;
  for (Eigen::Index t = 0; t < closed.numTriangles(); ++t) {
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (int k = 0; k < 3; ++k) centroid += closed.vertices.col(closed.triangles(k, t)) / 3.0;
    if (!(centroid.z() > 0.019 && centroid.x() > 0.02 && centroid.x() < 0.03 && std::abs(centroid.y()) < 0.005)) kept.push_back(t);
  }
  ASSERT_LT(static_cast<Eigen::Index>(kept.size()), closed.numTriangles());
  open.triangles.resize(3, static_cast<Eigen::Index>(kept.size()));
  for (size_t i = 0; i < kept.size(); ++i) open.triangles.col(static_cast<Eigen::Index>(i)) = closed.triangles.col(kept[i]);
  setRest(open);
  // A diagnostics message sent before the surface was installed may still arrive: wait for a current one.
  EXPECT_TRUE(waitFor([&] { return diagnosticValue("site density", 1.0).find("shell") != std::string::npos; }, 10.0))
      << diagnosticValue("site density");
  const Eigen::Matrix3Xf added = addedAt(dented, touch(0.0, 0.018));
  ASSERT_EQ(added.cols(), open.numVertices()) << "states of the open mesh flow";
  ASSERT_TRUE(added.allFinite());
  const Eigen::Index top = vertexNear(Eigen::Vector3d(0, 0, 0.02));
  EXPECT_NEAR(added(2, top), closedAdded(2, top), 0.25 * std::abs(closedAdded(2, top))) << "detail at the contact, as on the closed mesh";
  for (Eigen::Index v = 0; v < added.cols(); ++v) {
    if ((rest_.vertices.col(v) - Eigen::Vector3d(0, 0, 0.02)).norm() > 0.021) {
      ASSERT_EQ(added.col(v).norm(), 0.0f) << v;
    }
  }
}

TEST_F(EnrichmentKnobsTest, ToolTipFromTheUrdfDecidesProximity) {
  ros::NodeHandle privateNh("~");
  // "sphere": the node has a sphere tip of radius r from robot_description; "fallback": a broken
  // ~tool_tip_link, so the node must have logged the problem and use the pose position as a point tip.
  const std::string expect = privateNh.param<std::string>("expect_tool_tip", "sphere");
  const double r = privateNh.param("tip_radius", 0.004), contactDistance = privateNh.param("contact_distance", 0.001);
  const std::string tip = diagnosticValue("tool tip of tool_pose on tool_pose");
  if (expect == "sphere") {
    EXPECT_NE(tip.find("sphere r=" + std::to_string(r).substr(0, 5)), std::string::npos) << tip;
  } else {
    EXPECT_NE(tip.find("point (robot_description rejected"), std::string::npos) << tip;
  }
  const Eigen::Index top = vertexNear(Eigen::Vector3d(0, 0, 0.02));
  ASSERT_TRUE(roundTrip(goodState()));  // the surface the pose is compared with
  auto contactAtHeight = [&](double height) {
    geometry_msgs::PoseStamped pose;
    pose.header = header();
    pose.pose.position.x = rest_.vertices(0, top);
    pose.pose.position.y = rest_.vertices(1, top);
    pose.pose.position.z = rest_.vertices(2, top) + height;
    pose.pose.orientation.w = 1.0;
    posePub_.publish(pose);
    ros::WallDuration(0.3).sleep();
    sensor_msgs::PointCloud2 state = goodState();
    state.header.stamp = pose.header.stamp;
    if (!roundTrip(state)) return std::string("no output");
    const auto status = statusFor(state.header.stamp);
    if (!status) return std::string("no status");
    return status->tool_ids.empty() ? std::string("free") : status->tool_ids.front();
  };
  if (expect == "sphere") {
    EXPECT_EQ(contactAtHeight(r), "tool_pose") << "the sphere's surface touches the top at distance r";
    EXPECT_EQ(contactAtHeight(r + 0.5 * contactDistance), "tool_pose") << "within the contact distance";
    EXPECT_EQ(contactAtHeight(2 * r + contactDistance + 0.001), "free") << "2r + margin away";
  } else {
    EXPECT_EQ(contactAtHeight(r), "free") << "a point tip at distance r > contact distance";
    EXPECT_EQ(contactAtHeight(0.5 * contactDistance), "tool_pose");
  }
}

}  // namespace

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_enrichment_knobs");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
