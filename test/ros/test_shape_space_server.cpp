// Integration test of shape_space_server's services against a real master, and of de_smooth_bag on a
// recorded bag: results come back with the right sizes and headers, the path energy decreases, a rigid
// motion costs ~nothing, and bad input is answered with success = false and a message.
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <cstdlib>
#include <random>

#include "deformation_enrichment/BezierCurve.h"
#include "deformation_enrichment/ComputeGeodesic.h"
#include "deformation_enrichment/SmoothSequence.h"
#include "deformation_enrichment/mesh/grid_tet_mesh.hpp"
#include "deformation_enrichment/mesh/tet_surface.hpp"
#include "deformation_enrichment/ros/conversions.hpp"

namespace de = deformation_enrichment;

namespace {

const de::mesh::TriangleMesh& box() {
  static const de::mesh::TriangleMesh mesh =
      de::mesh::extractSurface(de::mesh::gridTetMesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0.6, 0.3), Eigen::Vector3i(5, 3, 2)))
          .surface;
  return mesh;
}

std_msgs::Header header(int i) {
  std_msgs::Header h;
  h.frame_id = "object";
  h.stamp = ros::Time(100 + i);
  return h;
}

// A bending motion with per-frame jitter (a noisy capture).
std::vector<Eigen::Matrix3Xf> noisySequence(int frames, double noise) {
  std::mt19937 random(7);
  std::normal_distribution<double> gauss(0.0, noise);
  std::vector<Eigen::Matrix3Xf> result;
  for (int f = 0; f < frames; ++f) {
    Eigen::Matrix3Xd v = box().vertices;
    const double bend = 0.3 * f / (frames - 1);
    for (Eigen::Index i = 0; i < v.cols(); ++i) {
      v(2, i) += bend * v(0, i) * v(0, i);
      for (int k = 0; k < 3; ++k) v(k, i) += gauss(random);
    }
    result.push_back(v.cast<float>());
  }
  return result;
}

// Temporal jitter of the shape itself: summed squared second differences of all edge lengths over time
// (intrinsic, since the shell energy, and so the flow, does not see rigid motions of single shapes).
double jitter(const std::vector<Eigen::Matrix3Xf>& frames) {
  const auto& tris = box().triangles;
  std::vector<Eigen::VectorXd> lengths;
  for (const auto& frame : frames) {
    Eigen::VectorXd l(3 * tris.cols());
    for (Eigen::Index t = 0; t < tris.cols(); ++t)
      for (int k = 0; k < 3; ++k) l[3 * t + k] = (frame.col(tris(k, t)) - frame.col(tris((k + 1) % 3, t))).cast<double>().norm();
    lengths.push_back(l);
  }
  double sum = 0.0;
  for (size_t f = 1; f + 1 < lengths.size(); ++f) sum += (lengths[f - 1] - 2 * lengths[f] + lengths[f + 1]).squaredNorm();
  return sum;
}

TEST(ShapeSpaceServer, SmoothSequenceLowersThePathEnergyAndKeepsHeaders) {
  ASSERT_TRUE(ros::service::waitForService("shape_space_server/smooth_sequence", 20000));
  de::SmoothSequence call;
  call.request.topology = de::ros_layer::messageFromTriangleMesh(box(), header(0));
  const auto frames = noisySequence(6, 0.004);
  for (size_t f = 0; f < frames.size(); ++f) call.request.shapes.push_back(de::ros_layer::cloudFromPositions(frames[f], header(int(f))));
  call.request.iterations = 3;
  call.request.tau = 0.5;
  ASSERT_TRUE(ros::service::call("shape_space_server/smooth_sequence", call));
  ASSERT_TRUE(call.response.success) << call.response.message;
  ASSERT_EQ(call.response.shapes.size(), frames.size());
  ASSERT_EQ(call.response.path_energy.size(), 4u);
  for (size_t k = 1; k < call.response.path_energy.size(); ++k)
    EXPECT_LE(call.response.path_energy[k], call.response.path_energy[k - 1]) << "iteration " << k;
  EXPECT_LT(call.response.path_energy.back(), call.response.path_energy.front());
  std::vector<Eigen::Matrix3Xf> smoothed;
  for (size_t f = 0; f < frames.size(); ++f) {
    EXPECT_EQ(call.response.shapes[f].header.stamp, call.request.shapes[f].header.stamp);
    smoothed.push_back(de::ros_layer::positionsFromCloud(call.response.shapes[f]));
    ASSERT_TRUE(smoothed.back().allFinite());
  }
  EXPECT_LT(jitter(smoothed), jitter(frames));
  EXPECT_GT(call.response.seconds, 0.0);
}

TEST(ShapeSpaceServer, GeodesicToARigidCopyIsNearlyFreeAndBezierHasTheSamples) {
  ASSERT_TRUE(ros::service::waitForService("shape_space_server/compute_geodesic", 20000));
  const Eigen::Matrix3Xf a = box().vertices.cast<float>();
  const Eigen::Matrix3f rotation = Eigen::AngleAxisf(0.4f, Eigen::Vector3f(0.2f, 1.0f, 0.3f).normalized()).toRotationMatrix();
  const Eigen::Matrix3Xf b = (rotation * a).colwise() + Eigen::Vector3f(0.3f, -0.1f, 0.2f);
  de::ComputeGeodesic geodesic;
  geodesic.request.topology = de::ros_layer::messageFromTriangleMesh(box(), header(0));
  geodesic.request.start = de::ros_layer::cloudFromPositions(a, header(0));
  geodesic.request.end = de::ros_layer::cloudFromPositions(b, header(1));
  geodesic.request.shapes = 5;
  ASSERT_TRUE(ros::service::call("shape_space_server/compute_geodesic", geodesic));
  ASSERT_TRUE(geodesic.response.success) << geodesic.response.message;
  EXPECT_EQ(geodesic.response.shapes.size(), 5u);
  EXPECT_LT(geodesic.response.length, 1e-3) << "float32 positions limit how rigid the copy is";

  de::BezierCurve bezier;
  bezier.request.topology = geodesic.request.topology;
  const auto frames = noisySequence(3, 0.0);
  for (int f = 0; f < 3; ++f) bezier.request.controls.push_back(de::ros_layer::cloudFromPositions(frames[f], header(f)));
  bezier.request.samples = 4;
  bezier.request.shapes_per_geodesic = 3;
  ASSERT_TRUE(ros::service::call("shape_space_server/bezier_curve", bezier));
  ASSERT_TRUE(bezier.response.success) << bezier.response.message;
  ASSERT_EQ(bezier.response.shapes.size(), 4u);
  EXPECT_LT((de::ros_layer::positionsFromCloud(bezier.response.shapes.front()) - frames.front()).cwiseAbs().maxCoeff(), 1e-5);
  EXPECT_LT((de::ros_layer::positionsFromCloud(bezier.response.shapes.back()) - frames.back()).cwiseAbs().maxCoeff(), 1e-5);
}

TEST(ShapeSpaceServer, BadInputIsAnsweredWithAMessage) {
  ASSERT_TRUE(ros::service::waitForService("shape_space_server/smooth_sequence", 20000));
  de::SmoothSequence call;
  call.request.topology = de::ros_layer::messageFromTriangleMesh(box(), header(0));
  const auto frames = noisySequence(3, 0.0);
  call.request.shapes = {de::ros_layer::cloudFromPositions(frames[0], header(0)), de::ros_layer::cloudFromPositions(frames[1], header(1))};
  ASSERT_TRUE(ros::service::call("shape_space_server/smooth_sequence", call));
  EXPECT_FALSE(call.response.success);
  EXPECT_NE(call.response.message.find("at least 3"), std::string::npos) << call.response.message;

  call.request.shapes.push_back(de::ros_layer::cloudFromPositions(frames[2].leftCols(frames[2].cols() - 1), header(2)));
  ASSERT_TRUE(ros::service::call("shape_space_server/smooth_sequence", call));
  EXPECT_FALSE(call.response.success) << "a shape with a different vertex count was accepted";

  Eigen::Matrix3Xf withNaN = frames[2];
  withNaN(0, 3) = std::numeric_limits<float>::quiet_NaN();
  call.request.shapes.back() = de::ros_layer::cloudFromPositions(withNaN, header(2));
  ASSERT_TRUE(ros::service::call("shape_space_server/smooth_sequence", call));
  EXPECT_FALSE(call.response.success) << "NaN was accepted";
}

TEST(DeSmoothBag, SmoothsTheTopicAndCopiesTheRest) {
  char self[4096];
  const ssize_t length = readlink("/proc/self/exe", self, sizeof(self) - 1);
  ASSERT_GT(length, 0);
  const std::string dir = std::string(self, size_t(length)).substr(0, std::string(self, size_t(length)).find_last_of('/'));
  const std::string in = ::testing::TempDir() + "de_smooth_in.bag", out = ::testing::TempDir() + "de_smooth_out.bag";
  const auto frames = noisySequence(6, 0.004);
  {
    rosbag::Bag bag(in, rosbag::bagmode::Write);
    bag.write("/rest_mesh", ros::Time(100), de::ros_layer::messageFromTriangleMesh(box(), header(0)));
    for (size_t f = 0; f < frames.size(); ++f) {
      bag.write("/mesh_state", ros::Time(100 + f), de::ros_layer::cloudFromPositions(frames[f], header(int(f))));
      std_msgs::Header other = header(int(f));
      bag.write("/other", ros::Time(100 + f), other);
    }
  }
  const std::string command = dir + "/de_smooth_bag --input " + in + " --output " + out +
                              " --topic /mesh_state --topology-topic /rest_mesh --iterations 3 > /dev/null";
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
  rosbag::Bag bag(out, rosbag::bagmode::Read);
  std::vector<Eigen::Matrix3Xf> smoothed;
  size_t others = 0, meshes = 0;
  for (const rosbag::MessageInstance& m : rosbag::View(bag)) {
    if (m.getTopic() == "/mesh_state") smoothed.push_back(de::ros_layer::positionsFromCloud(*m.instantiate<sensor_msgs::PointCloud2>()));
    if (m.getTopic() == "/other") ++others;
    if (m.getTopic() == "/rest_mesh") ++meshes;
  }
  ASSERT_EQ(smoothed.size(), frames.size());
  EXPECT_EQ(others, frames.size());
  EXPECT_EQ(meshes, 1u);
  EXPECT_LT(jitter(smoothed), jitter(frames));
  EXPECT_NE(std::system((dir + "/de_smooth_bag --input /nonexistent.bag --output " + out +
                         " --topic /mesh_state --topology-topic /rest_mesh 2> /dev/null").c_str()), 0);
}

}  // namespace

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_shape_space_server");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
