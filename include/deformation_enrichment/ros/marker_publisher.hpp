#pragma once
// The enrichment node's ~markers topic: keeps the last enriched state (shared pointers, no copy) and draws it
// (enrichment_markers.hpp) at ~marker_rate, decoding the point clouds only while someone subscribes.
#include <ros/node_handle.h>
#include <ros/timer.h>
#include <sensor_msgs/PointCloud2.h>

#include <functional>
#include <memory>
#include <mutex>
#include <vector>

#include "deformation_enrichment/enrichment/enrichment_session.hpp"
#include "deformation_enrichment/ros/contact_tracker.hpp"
#include "deformation_enrichment/ros/enrichment_markers.hpp"

namespace deformation_enrichment::ros_layer {

class MarkerPublisher {
public:
  /// The rest surface a state of `vertices` points lies on (null: none).
  using RestLookup = std::function<std::shared_ptr<const enrichment::RestSurface>(Eigen::Index vertices)>;

  /// Advertises ~markers on `privateNh` and draws at `rate` Hz on `nh`'s queue (0: never).
  MarkerPublisher(ros::NodeHandle nh, ros::NodeHandle privateNh, double rate, MarkerOptions options, RestLookup rest);

  /// The state to draw next: its input, what was published for it, and its contacts. Thread-safe.
  void keep(const sensor_msgs::PointCloud2ConstPtr& input, const sensor_msgs::PointCloud2ConstPtr& output,
            const std::vector<TrackedContact>& touching);

private:
  void draw(const ros::TimerEvent&);

  ros::Publisher publisher_;
  ros::Timer timer_;
  MarkerOptions options_;
  RestLookup rest_;
  std::mutex mutex_;  // guards the kept state below
  sensor_msgs::PointCloud2ConstPtr input_, output_;
  std::vector<TrackedContact> touching_;
};

}  // namespace deformation_enrichment::ros_layer
