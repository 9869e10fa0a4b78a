#include "deformation_enrichment/ros/marker_publisher.hpp"

#include <visualization_msgs/MarkerArray.h>

#include "deformation_enrichment/ros/conversions.hpp"

namespace deformation_enrichment::ros_layer {

MarkerPublisher::MarkerPublisher(ros::NodeHandle nh, ros::NodeHandle privateNh, double rate, MarkerOptions options,
                                 RestLookup rest)
    : options_(std::move(options)), rest_(std::move(rest)) {
  publisher_ = privateNh.advertise<visualization_msgs::MarkerArray>("markers", 1);
  if (rate > 0.0) timer_ = nh.createTimer(ros::Duration(1.0 / rate), &MarkerPublisher::draw, this);
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
  sensor_msgs::PointCloud2ConstPtr input, output;
  std::vector<TrackedContact> touching;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!input_) return;
    input = input_;
    output = output_;
    touching = touching_;
  }
  const Eigen::Matrix3Xf before = positionsFromCloud(*input), after = positionsFromCloud(*output);
  const std::shared_ptr<const enrichment::RestSurface> rest = rest_(before.cols());
  if (!rest) return;
  publisher_.publish(enrichmentMarkers(input->header, rest->geometry.surface, before, after, touching, options_));
}

}  // namespace deformation_enrichment::ros_layer
