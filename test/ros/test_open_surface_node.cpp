// The node on an open surface (docs/ros_api.md): ~scene slab gives the volume, the rest_mesh topic an open display
// surface (the slab's top alone) cut through 4.2 mm from the contact. A pressed state is enriched at the
// contact from the volume's site density, nothing reaches across the cut, every vertex outside the stamp is
// bit-identical; then the surface is cut again every few states while states stream at 60 Hz: every state
// comes out, none non-finite. The default slab example set (ctest slab_example_set) is loaded.
#include "enrichment_node_fixture.hpp"

#include "deformation_enrichment/scene_file/scene_description.hpp"
#include "deformation_enrichment/scenes/scene_models.hpp"

namespace {

using namespace enrichment_test;

// The top face of a closed surface (vertices kept, so states keep every vertex), split along x = cutX:
// vertices on that line are duplicated for the triangles beyond it, so the two sides share no vertex.
de::mesh::TriangleMesh openTopCutAt(const de::mesh::TriangleMesh& closed, double top, double cutX) {
  de::mesh::TriangleMesh open;
  open.vertices = closed.vertices;
  std::vector<Eigen::Vector3i> triangles;
  std::map<int, int> twin;
  for (Eigen::Index t = 0; t < closed.numTriangles(); ++t) {
    Eigen::Vector3i f = closed.triangles.col(t);
    bool onTop = true;
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (int k = 0; k < 3; ++k) {
      onTop = onTop && closed.vertices(2, f(k)) > top - 1e-6;
      centroid += closed.vertices.col(f(k)) / 3.0;
    }
    if (!onTop) continue;
    if (centroid.x() > cutX)
      for (int k = 0; k < 3; ++k) {
        if (std::abs(closed.vertices(0, f(k)) - cutX) > 1e-9) continue;
        auto [it, added] = twin.emplace(f(k), static_cast<int>(open.vertices.cols()));
        if (added) {
          open.vertices.conservativeResize(3, open.vertices.cols() + 1);
          open.vertices.col(it->second) = closed.vertices.col(f(k));
        }
        f(k) = it->second;
      }
    triangles.push_back(f);
  }
  open.triangles.resize(3, static_cast<Eigen::Index>(triangles.size()));
  for (std::size_t t = 0; t < triangles.size(); ++t) open.triangles.col(static_cast<Eigen::Index>(t)) = triangles[t];
  return open;
}

class OpenSurfaceTest : public EnrichmentNodeTest {
protected:
  void SetUp() override {
    EnrichmentNodeTest::SetUp();
    slab_ = de::scenes::sceneGeometry(de::scene_file::readSceneFile(de::scene_file::findSceneFile("slab"))).surface;
  }
  /// A dent of 2 mm under `p` (a smooth bump that fades over 8 mm), as the coarse state.
  Eigen::Matrix3Xf pressed(const Eigen::Vector3d& p) const {
    Eigen::Matrix3Xf x = rest_.vertices.cast<float>();
    for (Eigen::Index v = 0; v < x.cols(); ++v)
      x(2, v) -= static_cast<float>(0.002 * std::exp(-(rest_.vertices.col(v) - p).squaredNorm() / (2 * 0.008 * 0.008)));
    return x;
  }
  /// The enriched state of `state` with the tool at `p` (its current position), or empty if none came.
  Eigen::Matrix3Xf enriched(const Eigen::Matrix3Xf& state, const Eigen::Vector3d& p, std_msgs::Header& h) {
    h = header();
    de::ToolContactArray contacts;
    contacts.header = h;
    de::ToolContact contact;
    contact.tool_id = "tool";
    contact.in_contact = true;
    contact.position.x = p.x();
    contact.position.y = p.y();
    contact.position.z = p.z();
    contacts.contacts.push_back(contact);
    contactsPub_.publish(contacts);
    ros::WallDuration(0.1).sleep();
    if (!roundTrip(cloudFromPositions(state, h))) return {};
    return de::ros_layer::positionsFromCloud(*findEnriched(h.stamp));
  }

  de::mesh::TriangleMesh slab_;
};

TEST_F(OpenSurfaceTest, AnOpenCutSurfaceInTheSceneVolumeIsEnrichedAtTheContactAndNotAcrossTheCut) {
  // The contact on a top vertex near the middle; the cut one display cell (4.2 mm) beyond it in x.
  Eigen::Index centre = 0;
  (slab_.vertices.colwise() - Eigen::Vector3d(0.0, 0.0, 0.02)).colwise().squaredNorm().minCoeff(&centre);
  const Eigen::Vector3d p = slab_.vertices.col(centre);
  double cutX = 1.0;
  for (Eigen::Index v = 0; v < slab_.numVertices(); ++v)
    if (slab_.vertices(0, v) > p.x() + 1e-6) cutX = std::min(cutX, slab_.vertices(0, v));
  ASSERT_GT(cutX - p.x(), 0.003);
  ASSERT_LT(cutX - p.x(), 0.005);
  setRest(openTopCutAt(slab_, 0.02, cutX));
  EXPECT_TRUE(waitFor([&] { return diagnosticValue("site density", 1.0).find("volume") != std::string::npos; }, 10.0))
      << "the scene's volume gives the open surface its site density: " << diagnosticValue("site density");

  const Eigen::Matrix3Xf state = pressed(p);
  std_msgs::Header h;
  const Eigen::Matrix3Xf out = enriched(state, p - Eigen::Vector3d(0, 0, 0.002), h);
  ASSERT_EQ(out.cols(), state.cols());
  ASSERT_TRUE(out.allFinite());
  const Eigen::Matrix3Xf added = out - state;
  EXPECT_GT(added.colwise().norm().maxCoeff(), 5e-5f) << "detail at the contact";
  const double radius = 0.03;  // the slab set's stamp radius
  int beyond = 0;
  for (Eigen::Index v = 0; v < state.cols(); ++v) {
    const bool outside = (rest_.vertices.col(v) - p).norm() > radius;
    const bool acrossCut = rest_.vertices(0, v) > cutX + 1e-6 || v >= slab_.numVertices();  // twins lie on the far lip
    if (outside) {
      ASSERT_EQ(std::memcmp(out.col(v).data(), state.col(v).data(), 3 * sizeof(float)), 0) << "vertex " << v << " outside the stamp";
    } else if (acrossCut) {
      ++beyond;
      ASSERT_EQ(added.col(v).norm(), 0.0f) << "vertex " << v << " across the cut, " << (rest_.vertices.col(v) - p).norm() << " m away";
    }
  }
  EXPECT_GT(beyond, 20) << "the far lip lies within the stamp radius";
}

TEST_F(OpenSurfaceTest, CutsEveryFewStatesLoseNothingAndPublishNothingNonFinite) {
  const Eigen::Vector3d p(0.0, 0.0, 0.02);
  setRest(openTopCutAt(slab_, 0.02, 0.02));
  std::vector<double> cuts;
  for (int k = 0; k < 8; ++k) cuts.push_back(-0.03 + 0.0075 * k);
  int published = 0;
  std::vector<ros::Time> stamps;
  for (std::size_t c = 0; c < cuts.size(); ++c) {
    rest_ = openTopCutAt(slab_, 0.02, cuts[c]);
    restPub_.publish(de::ros_layer::messageFromTriangleMesh(rest_, header()));
    ros::WallDuration(0.05).sleep();  // the rest mesh goes ahead of the states of its topology
    const Eigen::Matrix3Xf state = pressed(p);
    de::ToolContactArray contacts;
    de::ToolContact contact;
    contact.tool_id = "tool";
    contact.in_contact = true;
    contact.position.z = 0.018;
    contacts.contacts.push_back(contact);
    for (int k = 0; k < 4; ++k) {  // a few states at 60 Hz, then the next cut
      const std_msgs::Header h = header();
      contacts.header = h;
      contactsPub_.publish(contacts);
      statePub_.publish(cloudFromPositions(state, h));
      stamps.push_back(h.stamp);
      ++published;
      ros::WallDuration(1.0 / 60.0).sleep();
      ros::spinOnce();
    }
  }
  EXPECT_TRUE(waitFor([&] {
    for (const ros::Time& stamp : stamps)
      if (!findEnriched(stamp)) return false;
    return true;
  }, 10.0)) << "every state comes out";
  int enrichedStates = 0, out = 0;
  for (const ros::Time& stamp : stamps) {
    const auto message = findEnriched(stamp);
    if (!message) continue;
    ++out;
    ASSERT_TRUE(de::ros_layer::positionsFromCloud(*message).allFinite()) << "non-finite output";
    const auto status = statusFor(stamp, 1.0);
    if (status && status->vertices_touched > 0) ++enrichedStates;
  }
  EXPECT_GT(enrichedStates, 0) << "some states were enriched between the cuts";
  std::printf("cuts every 4 states: %d states in, %d out, %d enriched (the others passed through while building)\n",
              published, out, enrichedStates);
}

}  // namespace

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_open_surface");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
