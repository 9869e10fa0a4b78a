// bullet_coarse_sim_node against the coarse-simulator contract (docs/coarse_simulator.md) on the slab: the
// latched rest_mesh is the scene's display surface; mesh_state has one finite point per display vertex; a
// servo_cp 3 mm into the top centre moves the display vertex there down by 1.5 to 3.5 mm (the bounds of
// unit_bullet_engine); a non-finite command and one in another frame are refused; reset brings the state
// back to rest.
#include <geometry_msgs/PoseStamped.h>
#include <gtest/gtest.h>
#include <pcl_msgs/PolygonMesh.h>
#include <ros/ros.h>
#include <sensor_msgs/PointCloud2.h>
#include <std_srvs/Empty.h>

#include <cmath>
#include <limits>

#include "deformation_enrichment/ros/conversions.hpp"
#include "deformation_enrichment/scene_file/scene_description.hpp"
#include "deformation_enrichment/scenes/scene_models.hpp"
#include "enrichment_node_fixture.hpp"

namespace {

using enrichment_test::waitFor;

constexpr double kDepth = 0.003;

class BulletCoarseSimTest : public ::testing::Test {
protected:
  void SetUp() override {
    scene_ = de::scene_file::readSceneFile(de::scene_file::findSceneFile("slab"));
    surface_ = de::scenes::buildSceneModels(scene_).surface;
    states_ = nh_.subscribe<sensor_msgs::PointCloud2>("mesh_state", 10, [this](const sensor_msgs::PointCloud2ConstPtr& m) {
      state_ = de::ros_layer::positionsFromCloud(*m);
      ++received_;
    });
    rests_ = nh_.subscribe<pcl_msgs::PolygonMesh>("rest_mesh", 1, [this](const pcl_msgs::PolygonMeshConstPtr& m) { rest_ = *m; });
    commands_ = nh_.advertise<geometry_msgs::PoseStamped>("servo_cp", 10);
    ASSERT_TRUE(waitFor([&] { return received_ > 0 && commands_.getNumSubscribers() > 0; }, 30.0)) << "no mesh_state, or no servo_cp subscriber";
  }

  // The next `n` states' last one.
  Eigen::Matrix3Xf nextState(int n = 1) {
    const long until = received_ + n;
    EXPECT_TRUE(waitFor([&] { return received_ >= until; }, 10.0)) << "mesh_state stopped";
    return state_;
  }
  // Waits until the state holds still (no vertex moves 1e-6 m over 3 states in a row) or `seconds` pass.
  Eigen::Matrix3Xf settledState(double seconds) {
    Eigen::Matrix3Xf previous = nextState();
    int quiet = 0;
    const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(seconds);
    while (quiet < 3 && ros::WallTime::now() < end) {
      const Eigen::Matrix3Xf x = nextState();
      quiet = (x - previous).colwise().norm().maxCoeff() < 1e-6f ? quiet + 1 : 0;
      previous = x;
    }
    return previous;
  }
  void command(const Eigen::Vector3d& centre, const std::string& frame = "slab") {
    std_msgs::Header header;
    header.frame_id = frame;
    header.stamp = ros::Time::now();
    commands_.publish(de::ros_layer::poseAt(centre, header));
  }
  Eigen::Index topCentreVertex() const {
    Eigen::Index v = 0;
    (surface_.vertices.colwise() - Eigen::Vector3d(0.0, 0.0, 0.02)).colwise().norm().minCoeff(&v);
    return v;
  }
  double largestDeviationFromRest(const Eigen::Matrix3Xf& x) const {
    return (x.cast<double>() - surface_.vertices).colwise().norm().maxCoeff();
  }

  ros::NodeHandle nh_;
  de::scene_file::SceneDescription scene_;
  de::mesh::TriangleMesh surface_;
  ros::Subscriber states_, rests_;
  ros::Publisher commands_;
  Eigen::Matrix3Xf state_;
  long received_ = 0;
  pcl_msgs::PolygonMesh rest_;
};

TEST_F(BulletCoarseSimTest, RestMeshAndStatesAreTheSlabsDisplaySurface) {
  ASSERT_TRUE(waitFor([&] { return !rest_.polygons.empty(); }, 10.0)) << "no latched rest_mesh";
  EXPECT_EQ(rest_.header.frame_id, "slab");
  const de::mesh::TriangleMesh rest = de::ros_layer::triangleMeshFromMessage(rest_);
  ASSERT_EQ(rest.numVertices(), surface_.numVertices());
  ASSERT_EQ(rest.numTriangles(), surface_.numTriangles());
  EXPECT_EQ(rest.triangles, surface_.triangles);
  EXPECT_LE((rest.vertices - surface_.vertices).cwiseAbs().maxCoeff(), 1e-6);  // float32 on the wire

  const Eigen::Matrix3Xf x = nextState();
  ASSERT_EQ(x.cols(), surface_.numVertices());
  EXPECT_TRUE(x.allFinite());
  EXPECT_LE(largestDeviationFromRest(x), 1e-6) << "untouched, the tissue stays at rest";
}

TEST_F(BulletCoarseSimTest, AnIndentationMovesTheSurfaceARefusedCommandDoesNotAndResetRestoresRest) {
  const Eigen::Index v = topCentreVertex();
  const Eigen::Vector3d centre = surface_.vertices.col(v) + (scene_.tool.radius - kDepth) * Eigen::Vector3d::UnitZ();
  command(centre);
  ASSERT_TRUE(waitFor([&] { return surface_.vertices(2, v) - state_(2, v) > 0.0015; }, 10.0))
      << "the vertex under the tool went down " << surface_.vertices(2, v) - state_(2, v) << " m in 10 s";
  const Eigen::Matrix3Xf pressed = settledState(10.0);
  ASSERT_TRUE(pressed.allFinite());
  const double down = surface_.vertices(2, v) - pressed(2, v);
  EXPECT_GE(down, 0.0015);
  EXPECT_LE(down, 0.0035);

  const double nan = std::numeric_limits<double>::quiet_NaN();
  command(Eigen::Vector3d(nan, 0.0, 0.02));
  command(Eigen::Vector3d(0.0, 0.0, 1.0), "world");  // would lift the tool off, were it taken
  const Eigen::Matrix3Xf after = nextState(20);
  ASSERT_TRUE(after.allFinite());
  EXPECT_LE((after - pressed).colwise().norm().maxCoeff(), 1e-5f) << "refused commands leave the tool where it was";

  std_srvs::Empty call;
  ASSERT_TRUE(ros::service::waitForService("reset", ros::Duration(10.0)));
  ASSERT_TRUE(ros::service::call("reset", call));
  const Eigen::Matrix3Xf reset = nextState(2);  // the first may have left before the call
  EXPECT_LE(largestDeviationFromRest(reset), 1e-6);
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_bullet_coarse_sim");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
