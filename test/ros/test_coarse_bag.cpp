// Recordings of a coarse simulator (ros/coarse_bag.hpp): written whole per interaction, read back exactly,
// resumed, and refused with the problem named when they are not usable. No master needed.
#include <gtest/gtest.h>
#include <rosbag/bag.h>
#include <std_msgs/String.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/ros/coarse_bag.hpp"
#include "deformation_enrichment/ros/conversions.hpp"
#include "../unit/acquisition/tiny_slab.hpp"

using namespace deformation_enrichment;

namespace {

constexpr long kVertices = 5;

std::vector<acquisition::PlanEntry> plan() {
  std::vector<acquisition::PlanEntry> p(3);
  p[0].point = Eigen::Vector3d(0.01, 0.0, 0.02), p[0].depth = 0.003;
  p[1].point = Eigen::Vector3d(-0.015, 0.01, 0.02), p[1].depth = 0.0025, p[1].drag = Eigen::Vector3d(0.0, 0.005, 0.0);
  p[2].point = Eigen::Vector3d(1.0 / 3.0, 0.0, 0.02), p[2].depth = 0.001;  // a value that needs all 17 digits
  return p;
}

ros_layer::SettledStep step(double z, long points = kVertices, const std::string& frame = "slab") {
  std_msgs::Header header;
  header.frame_id = frame;
  header.stamp = ros::Time(100.0 + z);
  ros_layer::SettledStep s;
  s.command.header = header;
  s.command.pose.position.z = z;
  Eigen::Matrix3Xf positions = Eigen::Matrix3Xf::Zero(3, points);
  positions.row(2).setConstant(static_cast<float>(z));
  s.state = ros_layer::cloudFromPositions(positions, header);
  return s;
}

std::string temporary(const std::string& name) {
  const std::string path = "/tmp/de_coarse_bag_" + std::to_string(::getpid()) + "_" + name;
  std::filesystem::remove(path);
  return path;
}

std::string readError(const std::string& path) {
  try {
    ros_layer::readCoarseBag(path, kVertices);
  } catch (const Error& e) {
    return e.what();
  }
  return "no error";
}

}  // namespace

TEST(CoarseBag, InteractionsReadBackWithTheirPlanSimulatorAndLastState) {
  const std::string path = temporary("roundtrip.bag");
  {
    ros_layer::CoarseBagWriter writer(path, plan(), "/bullet_coarse_sim");
    EXPECT_TRUE(writer.completed().empty());
    writer.write(0, {step(0.01), step(0.02)});
    writer.write(2, {step(0.03)});
  }
  const acquisition::RecordedCoarse r = ros_layer::readCoarseBag(path, kVertices);
  EXPECT_EQ(r.simulator, "/bullet_coarse_sim");
  ASSERT_EQ(r.plan.size(), 3u);
  EXPECT_EQ(r.plan[2].point.x(), 1.0 / 3.0);  // exact
  EXPECT_EQ(r.plan[1].drag, Eigen::Vector3d(0.0, 0.005, 0.0));
  ASSERT_EQ(r.settled.size(), 2u);
  EXPECT_FLOAT_EQ(static_cast<float>(r.settled.at(0)(2, 4)), 0.02f);  // the last step's state
  EXPECT_FLOAT_EQ(static_cast<float>(r.settled.at(2)(2, 0)), 0.03f);
  EXPECT_EQ(r.settled.count(1), 0u);
  // A resumed writer appends after the complete lines; another plan is refused.
  {
    ros_layer::CoarseBagWriter writer(path, plan(), "/bullet_coarse_sim");
    EXPECT_EQ(writer.completed(), (std::set<std::size_t>{0, 2}));
    writer.write(1, {step(0.04)});
  }
  EXPECT_EQ(ros_layer::readCoarseBag(path, kVertices).settled.size(), 3u);
  std::vector<acquisition::PlanEntry> other = plan();
  other[1].depth = 0.002;
  EXPECT_THROW(ros_layer::CoarseBagWriter(path, other, "x"), InvalidInputError);
  std::filesystem::remove(path);
}

TEST(CoarseBag, UnusableRecordingsAreRefusedWithTheProblemNamed) {
  const auto written = [](const std::string& name, const std::vector<ros_layer::SettledStep>& steps) {
    const std::string path = temporary(name);
    ros_layer::CoarseBagWriter(path, plan(), "sim").write(1, steps);
    return path;
  };
  EXPECT_NE(readError(written("count.bag", {step(0.01, 4)})).find("plan line 2: a state of 4 points for a display surface of 5 vertices"),
            std::string::npos);
  ros_layer::SettledStep bad = step(0.01);
  reinterpret_cast<float*>(bad.state.data.data())[2] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_NE(readError(written("nan.bag", {bad})).find("plan line 2: a non-finite state"), std::string::npos);
  ros_layer::SettledStep frame = step(0.01);
  frame.state.header.frame_id = "world";
  EXPECT_NE(readError(written("frame.bag", {frame})).find("a state in frame 'world', the commands in 'slab'"), std::string::npos);
  EXPECT_NE(readError(temporary("missing.bag")).find("cannot read the recording"), std::string::npos);

  const std::string cut = temporary("cut.bag");
  {
    ros_layer::CoarseBagWriter(cut, plan(), "sim");
    rosbag::Bag bag(cut, rosbag::bagmode::Append);
    std_msgs::String begin;
    begin.data = "begin 0";
    bag.write(ros_layer::kInteractionTopic, ros::Time(200.0), begin);
  }
  EXPECT_NE(readError(cut).find("plan line 1 was begun and not ended"), std::string::npos);

  const std::string typed = temporary("typed.bag");
  {
    rosbag::Bag bag(typed, rosbag::bagmode::Write);
    std_msgs::String text;
    text.data = "not a cloud";
    bag.write(ros_layer::kStateTopic, ros::Time(1.0), text);
  }
  EXPECT_NE(readError(typed).find("topic /mesh_state holds std_msgs/String, expected sensor_msgs/PointCloud2"), std::string::npos);

  const std::string empty = temporary("empty.bag");
  { ros_layer::CoarseBagWriter(empty, plan(), "sim"); }
  EXPECT_NE(readError(empty).find("no complete interaction"), std::string::npos);
  for (const char* name : {"count.bag", "nan.bag", "frame.bag", "cut.bag", "typed.bag", "empty.bag"}) std::filesystem::remove(temporary(name));
}

TEST(CoarseBag, ASessionOfTheUsersOwnToolsIsCutAtEachInteractionsLastCommand) {
  // servo_cp and mesh_state as `rosbag record` keeps them: line 1 ends where the tool reaches (0, 0, 0.01),
  // its settled state is the last before the tool moves away; line 2's end is never reached.
  const std::string path = temporary("session.bag");
  {
    rosbag::Bag bag(path, rosbag::bagmode::Write);
    const auto header = boost::make_shared<std::map<std::string, std::string>>();
    (*header)["callerid"] = "/my_simulator";  // a custom connection header carries the type too
    (*header)["type"] = ros::message_traits::datatype<sensor_msgs::PointCloud2>();
    (*header)["md5sum"] = ros::message_traits::md5sum<sensor_msgs::PointCloud2>();
    (*header)["message_definition"] = ros::message_traits::definition<sensor_msgs::PointCloud2>();
    const auto put = [&](double t, double z) {
      ros_layer::SettledStep s = step(z);
      bag.write("/servo_cp", ros::Time(t), s.command);
      bag.write("/sim/mesh_state", ros::Time(t + 0.01), s.state, header);
      bag.write("/sim/mesh_state", ros::Time(t + 0.02), step(z + 0.001).state, header);
    };
    put(1.0, 0.02);   // approaching
    put(2.0, 0.01);   // line 1's last centre: its states are z 0.01 and 0.011
    put(3.0, 0.05);   // moved away
  }
  const std::vector<Eigen::Vector3d> finals{Eigen::Vector3d(0.0, 0.0, 0.01), Eigen::Vector3d(0.0, 0.0, -1.0)};
  const acquisition::RecordedCoarse r = ros_layer::readSessionBag(path, kVertices, plan(), {finals[0], finals[1], finals[1]}, 1e-4);
  EXPECT_EQ(r.simulator, "/my_simulator");
  ASSERT_EQ(r.settled.size(), 1u);
  EXPECT_FLOAT_EQ(static_cast<float>(r.settled.at(0)(2, 0)), 0.011f);
  try {
    ros_layer::readSessionBag(path, kVertices, plan(), {finals[1], finals[1], finals[1]}, 1e-4);
    FAIL() << "no error";
  } catch (const InvalidInputError& e) {
    EXPECT_NE(std::string(e.what()).find("no interaction of the plan found"), std::string::npos) << e.what();
  }
  std::filesystem::remove(path);
}

TEST(CoarseBag, TheSameRecordingGivesTheSameSetByteForByte) {
  // A recording of the small slab's own coarse states, acquired twice from the bag.
  acquisition::SceneAcquisition acq(de_test::tinySlab());
  std::vector<acquisition::PlanEntry> p(2);
  p[0].point = Eigen::Vector3d(0.0, 0.0, 0.02), p[0].depth = 0.003;
  p[1].point = Eigen::Vector3d(0.01, 0.005, 0.02), p[1].depth = 0.002, p[1].drag = Eigen::Vector3d(0.003, 0.0, 0.0);
  const std::string path = temporary("own.bag");
  {
    ros_layer::CoarseBagWriter writer(path, p, "own");
    for (std::size_t line = 0; line < p.size(); ++line) {
      std_msgs::Header header;
      header.frame_id = "slab";
      header.stamp = ros::Time(10.0 + line);
      ros_layer::SettledStep s;
      s.command.header = header;
      s.state = ros_layer::cloudFromPositions(acq.simulate(p[line]).coarseOnFine.cast<float>(), header);
      writer.write(line, {s});
    }
  }
  const acquisition::RecordedCoarse recorded = ros_layer::readCoarseBag(path, acq.fineSurface().numVertices());
  const std::string a = temporary("set_a"), b = temporary("set_b");
  for (const std::string& dir : {a, b}) {
    std::filesystem::remove_all(dir);
    acq.acquireSet(recorded.plan, dir, nullptr, {}, &recorded);
  }
  for (const char* file : {"manifest.json", "stamps.bin"}) {
    std::ifstream x(a + "/" + file, std::ios::binary), y(b + "/" + file, std::ios::binary);
    const std::string bytesA((std::istreambuf_iterator<char>(x)), {}), bytesB((std::istreambuf_iterator<char>(y)), {});
    EXPECT_FALSE(bytesA.empty());
    EXPECT_EQ(bytesA, bytesB) << file << " differs";
  }
  for (const std::string& dir : {a, b}) std::filesystem::remove_all(dir);
  std::filesystem::remove(path);
}

int main(int argc, char** argv) {
  ros::Time::init();  // the writer stamps the plan with ros::Time::now(); no master is used
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
