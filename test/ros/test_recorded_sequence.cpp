// The enrichment node driven by a recorded sequence (test/data/slab_tap.bag: demo_scene_node's coarse
// Stable Neo-Hookean slab pressed and dragged by a tool, then released; 31 states at 10 Hz with contacts,
// rosbag record + filter + lz4). Checks, against a real master: vertices outside every stamp radius are
// bit-identical to the input; the example's detail appears at the contact; a corrupt example set is
// rejected while the old one stays active; after lift-off detail stays only at the released site; two tools
// give a continuous surface.
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <mutex>

#include "deformation_enrichment/LoadExampleSet.h"
#include "deformation_enrichment/ToolContactArray.h"
#include "deformation_enrichment/enrichment/contact_enricher.hpp"
#include "deformation_enrichment/examples/example_set_io.hpp"
#include "deformation_enrichment/mesh/surface_projection.hpp"
#include "deformation_enrichment/ros/conversions.hpp"
#include "enrichment_node_fixture.hpp"

namespace {

using enrichment_test::waitFor;

constexpr double kRadius = 0.02;    // stamp radius of the test's example
constexpr double kDetail = 0.001;   // the example's stamp: 1 mm into the surface

struct Frame {
  sensor_msgs::PointCloud2 state;
  de::ToolContactArray contacts;
  Eigen::Matrix3Xd positions;
};

class RecordedSequenceTest : public ::testing::Test {
protected:
  void SetUp() override {
    std::string bagPath;
    ASSERT_TRUE(ros::NodeHandle("~").getParam("bag", bagPath)) << "~bag not set";
    rosbag::Bag bag(bagPath, rosbag::bagmode::Read);
    std::map<ros::Time, de::ToolContactArray> contacts;
    for (const rosbag::MessageInstance& m : rosbag::View(bag)) {
      if (auto mesh = m.instantiate<pcl_msgs::PolygonMesh>()) restMessage_ = *mesh;
      if (auto c = m.instantiate<de::ToolContactArray>()) contacts[c->header.stamp] = *c;
      if (auto s = m.instantiate<sensor_msgs::PointCloud2>())
        frames_.push_back({*s, {}, de::ros_layer::positionsFromCloud(*s).cast<double>()});
    }
    for (Frame& f : frames_) {
      ASSERT_TRUE(contacts.count(f.state.header.stamp)) << "a recorded state has no contacts message";
      f.contacts = contacts[f.state.header.stamp];
    }
    ASSERT_GE(frames_.size(), 20u);
    rest_ = de::ros_layer::triangleMeshFromMessage(restMessage_);

    restPub_ = nh_.advertise<pcl_msgs::PolygonMesh>("rest_mesh", 1, true);
    statePub_ = nh_.advertise<sensor_msgs::PointCloud2>("mesh_state", 50);
    contactsPub_ = nh_.advertise<de::ToolContactArray>("contacts", 50);
    enrichedSub_ = nh_.subscribe("enriched_mesh_state", 50, &RecordedSequenceTest::onEnriched, this);
    ASSERT_TRUE(waitFor([&] {
      return statePub_.getNumSubscribers() > 0 && contactsPub_.getNumSubscribers() > 0 && restPub_.getNumSubscribers() > 0 &&
             enrichedSub_.getNumPublishers() > 0;
    }, 20.0)) << "the enrichment node did not come up";
    restPub_.publish(restMessage_);
  }

  /// Sends a frame (contacts first, as the scene does) and returns the node's output positions for it
  /// (no columns when none arrived within `seconds`).
  Eigen::Matrix3Xd play(Frame frame, double seconds = 5.0) {
    frame.state.header.stamp = frame.contacts.header.stamp = nextStamp_;
    for (auto& c : frame.contacts.contacts) c.header.stamp = nextStamp_;
    nextStamp_ += ros::Duration(0.1);
    contactsPub_.publish(frame.contacts);
    ros::WallDuration(0.05).sleep();  // separate topics: let the contacts arrive before the state
    statePub_.publish(frame.state);
    sensor_msgs::PointCloud2ConstPtr out;
    waitFor([&] { return (out = find(frame.state.header.stamp)) != nullptr; }, seconds);
    return out ? de::ros_layer::positionsFromCloud(*out).cast<double>() : Eigen::Matrix3Xd();
  }

  sensor_msgs::PointCloud2ConstPtr find(const ros::Time& stamp) {
    std::lock_guard<std::mutex> lock(mutex_);
    for (const auto& m : enriched_)
      if (m->header.stamp == stamp) return m;
    return nullptr;
  }
  void onEnriched(const sensor_msgs::PointCloud2ConstPtr& m) { std::lock_guard<std::mutex> l(mutex_); enriched_.push_back(m); }

  /// The frame whose tool is deepest: the example is described there.
  std::size_t deepest() const {
    std::size_t best = 0;
    double lowest = 1e9;
    for (std::size_t i = 0; i < frames_.size(); ++i)
      for (const auto& c : frames_[i].contacts.contacts)
        if (c.position.z < lowest) lowest = c.position.z, best = i;
    return best;
  }

  /// Rest position of the surface point under a contact (nearest current vertex, as the node maps it).
  /// Where the node puts a contact: the nearest point of the current surface (CGAL's AABB tree here, an
  /// independent search), mapped to the rest surface with its barycentric coordinates.
  Eigen::Vector3d restContact(const Frame& frame, const de::ToolContact& c) const {
    de::mesh::TriangleMesh current = rest_;
    current.vertices = frame.positions;
    const de::mesh::SurfacePoint s =
        de::mesh::SurfaceProjector(current).project(Eigen::Vector3d(c.position.x, c.position.y, c.position.z));
    return rest_.vertices(Eigen::all, rest_.triangles.col(s.triangle)) * s.barycentric;
  }

  /// A one-example set described by the package's own pipeline at frame `at`: stamp kDetail inwards.
  void writeExampleSet(const Frame& at, const std::string& directory) const {
    de::enrichment::ContactEnricherOptions options;
    options.descriptors.window.scale = 0.006;
    options.sampleSpacing = 0.002;
    options.stampRadius = kRadius;
    const de::enrichment::ContactEnricher describer(rest_, options);
    de::enrichment::Contact contact;
    contact.point = Eigen::Vector3d(at.contacts.contacts.at(0).position.x, at.contacts.contacts.at(0).position.y,
                                    at.contacts.contacts.at(0).position.z);
    contact.restState = false;
    const auto d = describer.describe(at.positions, contact);
    de::examples::Example e;
    e.contact = d.p;
    e.frame = d.B;
    e.rho = d.rho;
    e.mu = d.mu;
    e.stamp = cv::Mat(32, 32, CV_32FC3, cv::Scalar(0.0f, 0.0f, -static_cast<float>(kDetail)));
    e.stampRadius = kRadius;
    de::examples::ExampleSet set;
    set.metadata.scene = "slab";
    set.metadata.material["window_scale_m"] = 0.006;
    set.metadata.material["site_sample_spacing_m"] = 0.002;
    set.examples.push_back(e);
    de::examples::saveExampleSet(set, directory);
  }

  /// Plays every frame: untouched vertices keep their bits; with a contact, detail appears under it; before
  /// the press the output is the input, and after the lift-off only the released site (the last contact's
  /// rest point) may carry detail. `deepestOutput`: the output of frame `at`.
  void replayWholeRecording(std::size_t at, Eigen::Matrix3Xd& deepestOutput) {
    int withDetail = 0, withoutContact = 0;
    std::vector<Eigen::Vector3d> released;
    for (std::size_t i = 0; i < frames_.size(); ++i) {
      const Frame& f = frames_[i];
      const Eigen::Matrix3Xd out = play(f);
      ASSERT_EQ(out.cols(), f.positions.cols()) << "frame " << i << ": no output";
      const Eigen::Matrix3Xf in = f.positions.cast<float>(), got = out.cast<float>();
      std::vector<Eigen::Vector3d> centres;
      for (const auto& c : f.contacts.contacts) centres.push_back(restContact(f, c));
      if (!centres.empty()) released = centres;
      const bool touching = !centres.empty();
      if (!touching) centres = released;
      double under = 0.0;
      for (Eigen::Index v = 0; v < in.cols(); ++v) {
        bool inside = false;
        for (const auto& p : centres) inside = inside || (rest_.vertices.col(v) - p).norm() < kRadius;
        if (!inside) {
          ASSERT_EQ(got.col(v), in.col(v)) << "frame " << i << ": vertex " << v << " outside every stamp changed";
        }
        for (const auto& p : centres)
          if ((rest_.vertices.col(v) - p).norm() < 0.003) under = std::min(under, double(got(2, v) - in(2, v)));
      }
      if (!touching) {
        ++withoutContact;
        if (released.empty()) {
          EXPECT_EQ(got, in) << "frame " << i << " is before any contact but was changed";
        }
      } else if (under < -0.3 * kDetail) {
        ++withDetail;
      }
      if (i == at) {
        deepestOutput = out;
        EXPECT_LT(under, -0.5 * kDetail) << "the example's own frame must get most of its 1 mm";
      }
    }
    RecordProperty("frames_with_detail", withDetail);
    RecordProperty("frames_without_contact", withoutContact);
    EXPECT_GE(withoutContact, 2) << "the recording should include the lift-off";
    EXPECT_GE(withDetail, 5);
  }

  /// Two tools 8 mm apart at frame `at`: overlapping stamps neither add up nor make the surface rougher than
  /// one stamp (`deepestOutput`: the one-tool output there).
  void twoToolsAsSmoothAsOne(std::size_t at, const Eigen::Matrix3Xd& deepestOutput) {
    const auto edgeJump = [&](const Eigen::Matrix3Xd& e) {
      double jump = 0.0;
      for (Eigen::Index t = 0; t < rest_.triangles.cols(); ++t)
        for (int k = 0; k < 3; ++k)
          jump = std::max(jump, (e.col(rest_.triangles(k, t)) - e.col(rest_.triangles((k + 1) % 3, t))).norm());
      return jump;
    };
    const Eigen::Matrix3Xd one = deepestOutput - frames_[at].positions;
    Frame twoTools = frames_[at];
    de::ToolContact second = twoTools.contacts.contacts.at(0);
    second.tool_id = "second_tool";
    second.position.x += 0.008;
    twoTools.contacts.contacts.push_back(second);
    const Eigen::Matrix3Xd two = play(twoTools) - frames_[at].positions;
    ASSERT_EQ(two.cols(), one.cols());
    EXPECT_LE(two.colwise().norm().maxCoeff(), 1.05 * one.colwise().norm().maxCoeff()) << "stamps added up";
    EXPECT_LE(edgeJump(two), 1.5 * edgeJump(one) + 1e-6) << "overlapping stamps made the surface rough";
    EXPECT_GT((two - one).cwiseAbs().maxCoeff(), 0.0) << "the second tool had no effect";
  }

  bool load(const std::string& path, std::string* message = nullptr) {
    de::LoadExampleSet call;
    call.request.path = path;
    EXPECT_TRUE(ros::service::waitForService("enrichment/load_example_set", 10000));
    EXPECT_TRUE(ros::service::call("enrichment/load_example_set", call));
    if (message) *message = call.response.message;
    return call.response.success;
  }

  ros::NodeHandle nh_;
  ros::Publisher restPub_, statePub_, contactsPub_;
  ros::Subscriber enrichedSub_;
  std::mutex mutex_;
  std::vector<sensor_msgs::PointCloud2ConstPtr> enriched_;
  pcl_msgs::PolygonMesh restMessage_;
  de::mesh::TriangleMesh rest_;
  std::vector<Frame> frames_;
  ros::Time nextStamp_{2000, 0};
};

TEST_F(RecordedSequenceTest, EnrichesAtTheContactOnlyKeepsItsSetAndContinuity) {
  const std::string good = ::testing::TempDir() + "de_recorded_set", bad = ::testing::TempDir() + "de_recorded_bad_set";
  const std::size_t at = deepest();
  writeExampleSet(frames_[at], good);
  ASSERT_TRUE(waitFor([&] { return play(frames_.front(), 0.3).cols() > 0; }, 20.0)) << "rest mesh never became active";
  ASSERT_TRUE(load(good));

  Eigen::Matrix3Xd deepestOutput;
  ASSERT_NO_FATAL_FAILURE(replayWholeRecording(at, deepestOutput));

  // A corrupt set is rejected and the old one stays active: the same frame gives the same output.
  std::filesystem::remove_all(bad);
  std::filesystem::copy(good, bad);
  std::filesystem::resize_file(std::filesystem::path(bad) / "stamps.bin", 100);
  std::string message;
  EXPECT_FALSE(load(bad, &message));
  EXPECT_FALSE(message.empty());
  // Replaying the touch that led to the deepest frame, after the tissue is back at rest (so no site the
  // recording's last tap released is still enriched), gives the same stamping frame memory (previous b_x)
  // as the first time, so the same output, where another set or none would change the 1 mm of detail.
  Frame atRest = frames_.front();
  atRest.contacts.contacts.clear();
  de::ros_layer::writePositions(rest_.vertices.cast<float>(), atRest.state);
  for (int k = 0; k < 3; ++k) play(atRest);
  std::size_t touchStart = at;
  while (touchStart > 0 && !frames_[touchStart - 1].contacts.contacts.empty()) --touchStart;
  Eigen::Matrix3Xd replayed;
  for (std::size_t i = touchStart; i <= at; ++i) replayed = play(frames_[i]);
  ASSERT_EQ(replayed.cols(), deepestOutput.cols());
  EXPECT_LT((replayed - deepestOutput).cwiseAbs().maxCoeff(), 1e-6) << "the old set must stay active after a corrupt one";

  ASSERT_NO_FATAL_FAILURE(twoToolsAsSmoothAsOne(at, deepestOutput));
  std::filesystem::remove_all(good);
  std::filesystem::remove_all(bad);
}

}  // namespace

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_recorded_sequence");
  ros::NodeHandle keep;  // keeps the node alive across tests
  return RUN_ALL_TESTS();
}
