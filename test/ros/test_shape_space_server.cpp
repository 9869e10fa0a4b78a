// Integration test of shape_space_server's services against a real master, and of de_smooth_bag on a
// recorded bag and on real noisy captures (MD2 clips of [assimp-testmodels]): results come back with the right sizes and headers, the path energy decreases, a rigid
// motion costs ~nothing, and bad input is answered with success = false and a message.
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <random>
#include <string>

#include "deformation_enrichment/BezierCurve.h"
#include "deformation_enrichment/ComputeGeodesic.h"
#include "deformation_enrichment/SmoothSequence.h"
#include "deformation_enrichment/mesh/grid_tet_mesh.hpp"
#include "deformation_enrichment/mesh/tet_surface.hpp"
#include "deformation_enrichment/ros/conversions.hpp"
#include "../unit/shape_space/real_sequences.hpp"

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

// The directory of this test's executable, where catkin puts de_smooth_bag too.
std::string toolDirectory() {
  char self[4096];
  const ssize_t length = readlink("/proc/self/exe", self, sizeof(self) - 1);
  const std::string path(self, size_t(std::max<ssize_t>(length, 0)));
  return path.substr(0, path.find_last_of('/'));
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
  const std::string dir = toolDirectory();
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

// Real, noisy captures through de_smooth_bag as a user runs it (defaults: full space; the restoring force
// of de_smooth), judged as test_real_sequences judges de_smooth: every step accepted, eq. 4 falling, the
// shapes' motion smoother, and less volume change than the Gaussian filter wherever that filter needs a
// wide kernel ([Brandt16 Fig. 8]). Both captures end smoother than any width of the filter.
// The server and the command-line tool use the same energy (the bending weight scaled to the mesh size) and
// the same flow, so the same sequence gives the same result through either.
TEST(DeSmoothBag, GivesWhatTheServerGivesForTheSameSequence) {
  ASSERT_TRUE(ros::service::waitForService("shape_space_server/smooth_sequence", 20000));
  const auto frames = noisySequence(6, 0.004);
  de::SmoothSequence call;
  call.request.topology = de::ros_layer::messageFromTriangleMesh(box(), header(0));
  for (size_t f = 0; f < frames.size(); ++f) call.request.shapes.push_back(de::ros_layer::cloudFromPositions(frames[f], header(int(f))));
  call.request.iterations = 3;
  call.request.tau = 0.5;
  ASSERT_TRUE(ros::service::call("shape_space_server/smooth_sequence", call));
  ASSERT_TRUE(call.response.success) << call.response.message;
  const std::string in = ::testing::TempDir() + "de_smooth_same_in.bag", out = ::testing::TempDir() + "de_smooth_same_out.bag";
  {
    rosbag::Bag bag(in, rosbag::bagmode::Write);
    bag.write("/rest_mesh", ros::Time(100), call.request.topology);
    for (size_t f = 0; f < frames.size(); ++f) bag.write("/mesh_state", ros::Time(100 + f), call.request.shapes[f]);
  }
  const std::string command = toolDirectory() + "/de_smooth_bag --input " + in + " --output " + out +
                              " --topic /mesh_state --topology-topic /rest_mesh --iterations 3 --tau 0.5 > /dev/null 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
  rosbag::Bag bag(out, rosbag::bagmode::Read);
  size_t f = 0;
  double largest = 0.0, moved = 0.0;
  for (const rosbag::MessageInstance& m : rosbag::View(bag, rosbag::TopicQuery("/mesh_state"))) {
    ASSERT_LT(f, frames.size());
    const Eigen::Matrix3Xf tool = de::ros_layer::positionsFromCloud(*m.instantiate<sensor_msgs::PointCloud2>());
    const Eigen::Matrix3Xf server = de::ros_layer::positionsFromCloud(call.response.shapes[f]);
    largest = std::max(largest, double((tool - server).cwiseAbs().maxCoeff()));
    moved = std::max(moved, double((server - frames[f]).cwiseAbs().maxCoeff()));
    ++f;
  }
  EXPECT_EQ(f, frames.size());
  EXPECT_GT(moved, 1e-4);         // smoothing moved the shapes
  EXPECT_LT(largest, 1e-6);       // and both paths agree to float precision
}

TEST(DeSmoothBag, SmoothsRealNoisyCapturesWithFallingPathEnergyAndLessDistortionThanTheFilter) {
  namespace st = de::shape_space::test;
  std::vector<std::pair<std::string, de::shape_space::ShapeSequence>> captures;
  const de::mesh::Md2Animation faerie = de::mesh::readMd2(std::string(st::kMd2Directory) + "faerie.md2");
  const de::mesh::Md2Animation sydney = de::mesh::readMd2(std::string(st::kMd2Directory) + "sydney.md2");
  captures.emplace_back("faerie run", st::noisyClip(faerie, st::Clip{"run", 40, 45}, 0.003, 11));
  captures.emplace_back("sydney crwalk", st::noisyClip(sydney, st::Clip{"crwalk", 154, 159}, 0.002, 12));
  for (const auto& [name, input] : captures) {
    const std::string in = ::testing::TempDir() + "de_smooth_real_in.bag", out = ::testing::TempDir() + "de_smooth_real_out.bag";
    std::vector<Eigen::VectorXd> sent;  // what the bag holds: float32 positions
    {
      rosbag::Bag bag(in, rosbag::bagmode::Write);
      bag.write("/rest_mesh", ros::Time(100), de::ros_layer::messageFromTriangleMesh({de::shape_space::unflatten(input.shapes[0]), input.triangles}, header(0)));
      for (size_t f = 0; f < input.shapes.size(); ++f) {
        const Eigen::Matrix3Xf frame = de::shape_space::unflatten(input.shapes[f]).cast<float>();
        bag.write("/mesh_state", ros::Time(100 + f), de::ros_layer::cloudFromPositions(frame, header(int(f))));
        sent.push_back(de::shape_space::flatten(frame.cast<double>()));
      }
    }
    const std::string command = toolDirectory() + "/de_smooth_bag --input " + in + " --output " + out +
                                " --topic /mesh_state --topology-topic /rest_mesh --iterations 3 --restoring 0.05 2> /dev/null";
    FILE* pipe = popen(command.c_str(), "r");
    ASSERT_NE(pipe, nullptr);
    std::string json;
    char buffer[4096];
    while (fgets(buffer, sizeof(buffer), pipe)) json += buffer;
    ASSERT_EQ(pclose(pipe), 0) << name << ": " << command;
    const auto report = nlohmann::json::parse(json);
    EXPECT_EQ(report["accepted_steps"].get<int>(), 3) << name;
    const std::vector<double> energies = report["path_energy"].get<std::vector<double>>();
    ASSERT_EQ(energies.size(), 4u) << name;
    for (size_t k = 1; k < energies.size(); ++k) EXPECT_LT(energies[k], energies[k - 1]) << name << " step " << k;
    std::vector<Eigen::VectorXd> smoothed;
    rosbag::Bag bag(out, rosbag::bagmode::Read);
    for (const rosbag::MessageInstance& m : rosbag::View(bag, rosbag::TopicQuery("/mesh_state")))
      smoothed.push_back(de::shape_space::flatten(de::ros_layer::positionsFromCloud(*m.instantiate<sensor_msgs::PointCloud2>()).cast<double>()));
    ASSERT_EQ(smoothed.size(), sent.size()) << name;
    const auto intrinsic = [&](const std::vector<Eigen::VectorXd>& x) { return st::intrinsicRoughness(x, input.triangles); };
    const double roughness = intrinsic(smoothed);
    EXPECT_LT(roughness, intrinsic(sent)) << name;
    // Held to the narrowest filter as smooth as the output, or to the smoothest filter if none is (the output
    // is then smoother than the filter it is held to).
    const st::FilterTuning filterTuning = st::tuneFilter(sent, roughness, intrinsic);
    const st::Distortion flow = st::distortion(sent, smoothed, input.triangles);
    const st::Distortion filter = st::distortion(sent, st::gaussianFilter(sent, filterTuning.sigma), input.triangles);
    std::printf("%s: roughness x%.3f, filter sigma %.2f%s (x%.3f), volume change %.4f vs filter %.4f, edge change %.4f vs %.4f\n",
                name.c_str(), roughness / intrinsic(sent), filterTuning.sigma, filterTuning.reached ? "" : " (smoothest)",
                filterTuning.roughness / intrinsic(sent), flow.volume, filter.volume, flow.edge, filter.edge);
    EXPECT_GE(filterTuning.sigma, 1.5) << name << ": these clips move too much for a narrow filter";
    EXPECT_LT(flow.volume, filter.volume) << name;
  }
}

}  // namespace

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_shape_space_server");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
