#include "deformation_enrichment/ros/marker_publisher.hpp"

#include <visualization_msgs/MarkerArray.h>

#include <optional>
#include <string>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/ros/conversions.hpp"

namespace deformation_enrichment::ros_layer {
namespace {
// Fine states kept for matching the drawn state's stamp: half a second of a 60 Hz stream, while a draw
// needs only those that arrived since the last one.
constexpr std::size_t kFineStatesKept = 32;

// A fine state's positions, when it is a usable truth for `state` (`vertices` points); else why not.
std::optional<Eigen::Matrix3Xf> fineTruth(const sensor_msgs::PointCloud2& fine, const std_msgs::Header& state, Eigen::Index vertices,
                                          std::string& reason, std::string& detail) {
  if (fine.header.frame_id != state.frame_id) {
    reason = "frame differs from the mesh state's";
    detail = "'" + fine.header.frame_id + "' for a state in '" + state.frame_id + "'";
    return std::nullopt;
  }
  try {
    Eigen::Matrix3Xf truth = positionsFromCloud(fine);
    if (truth.cols() != vertices) {
      reason = "point count differs from the mesh state";
      detail = std::to_string(truth.cols()) + " points for a state of " + std::to_string(vertices);
    } else if (!truth.allFinite()) {
      reason = "non-finite point";
      detail = "not drawing the fine truth of this state";
    } else {
      return truth;
    }
  } catch (const Error& e) {
    reason = "invalid point cloud";
    detail = e.what();
  }
  return std::nullopt;
}

}  // namespace

MarkerPublisher::MarkerPublisher(ros::NodeHandle nh, ros::NodeHandle privateNh, double rate, MarkerOptions options,
                                 RestLookup rest, Reject reject)
    : options_(std::move(options)), rest_(std::move(rest)), reject_(std::move(reject)) {
  publisher_ = privateNh.advertise<visualization_msgs::MarkerArray>("markers", 1);
  if (rate <= 0.0) return;
  nh.setCallbackQueue(&queue_);
  timer_ = nh.createTimer(ros::Duration(1.0 / rate), &MarkerPublisher::draw, this);
  if (!options_.fineOffset.isZero()) fineSubscriber_ = nh.subscribe("fine_state", 4, &MarkerPublisher::keepFine, this);
  spinner_ = std::make_unique<ros::AsyncSpinner>(1, &queue_);
  spinner_->start();
}

MarkerPublisher::~MarkerPublisher() {
  if (spinner_) spinner_->stop();  // no draw runs past this point
}

void MarkerPublisher::keepFine(const sensor_msgs::PointCloud2ConstPtr& fine) {
  std::lock_guard<std::mutex> lock(mutex_);
  fine_.push_back(fine);
  if (fine_.size() > kFineStatesKept) fine_.pop_front();
}

sensor_msgs::PointCloud2ConstPtr MarkerPublisher::fineAt(const ros::Time& stamp) const {
  sensor_msgs::PointCloud2ConstPtr newest;
  for (const auto& fine : fine_)
    if (fine->header.stamp <= stamp && (!newest || fine->header.stamp >= newest->header.stamp)) newest = fine;
  return newest && stamp - newest->header.stamp <= ros::Duration(options_.fineStampTolerance) ? newest : nullptr;
}

void MarkerPublisher::keep(const sensor_msgs::PointCloud2ConstPtr& input, const sensor_msgs::PointCloud2ConstPtr& output,
                           const std::vector<TrackedContact>& touching) {
  std::lock_guard<std::mutex> lock(mutex_);
  input_ = input;
  output_ = output;
  touching_ = touching;
}

void MarkerPublisher::draw(const ros::TimerEvent&) {
  if (publisher_.getNumSubscribers() == 0) return;  // markers cost megabytes: only for an audience
  sensor_msgs::PointCloud2ConstPtr input, output, fine;
  std::vector<TrackedContact> touching;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!input_) return;
    input = input_;
    output = output_;
    touching = touching_;
    fine = fineAt(input_->header.stamp);
  }
  const Eigen::Matrix3Xf before = positionsFromCloud(*input), after = positionsFromCloud(*output);
  const std::shared_ptr<const enrichment::RestSurface> rest = rest_(before.cols());
  if (!rest) return;
  std::optional<Eigen::Matrix3Xf> truth;
  if (fine) {
    std::string reason, detail;
    truth = fineTruth(*fine, input->header, before.cols(), reason, detail);
    if (!truth) reject_("fine_state", reason, detail);
  }
  publisher_.publish(enrichmentMarkers(input->header, rest->geometry.surface, before, after, touching, options_,
                                       truth ? &*truth : nullptr));
}

}  // namespace deformation_enrichment::ros_layer
