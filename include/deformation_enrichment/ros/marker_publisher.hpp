#pragma once
// The enrichment node's ~markers topic: keeps the last enriched state (shared pointers, no copy) and draws it
// (enrichment_markers.hpp) at ~marker_rate, decoding the point clouds only while someone subscribes. With a
// fine offset it also listens to fine_state, the fine simulation's states of the input stream (a demo or an
// evaluation publishes them with the stamps of the mesh states they belong to; a demo driving a simulator that
// runs on its own, with the stamps of its tool commands), and draws the newest one stamped at or before the
// drawn state, within ~marker_fine_tolerance, beside it. It draws on a thread and callback queue of its own,
// so a draw (decoding and triangulating up to three surfaces) never delays a state.
#include <ros/callback_queue.h>
#include <ros/node_handle.h>
#include <ros/spinner.h>
#include <ros/timer.h>
#include <sensor_msgs/PointCloud2.h>

#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "deformation_enrichment/enrichment/enrichment_session.hpp"
#include "deformation_enrichment/ros/contact_tracker.hpp"
#include "deformation_enrichment/ros/enrichment_markers.hpp"

namespace deformation_enrichment::ros_layer {

class MarkerPublisher {
public:
  /// The rest surface a state of `vertices` points lies on (null: none).
  using RestLookup = std::function<std::shared_ptr<const enrichment::RestSurface>(Eigen::Index vertices)>;

  /// Counts and logs a refused input: (input, reason, detail), as the node's /diagnostics do.
  using Reject = std::function<void(const std::string&, const std::string&, const std::string&)>;

  /// Advertises ~markers on `privateNh` and draws at `rate` Hz (0: never); subscribes to fine_state on `nh`
  /// when options.fineOffset is not zero. A fine state that cannot be the drawn state's truth (another frame,
  /// point count, a non-finite point, a broken cloud) goes to `reject`, once for each draw that finds it.
  MarkerPublisher(ros::NodeHandle nh, ros::NodeHandle privateNh, double rate, MarkerOptions options, RestLookup rest,
                  Reject reject);
  ~MarkerPublisher();

  /// The state to draw next: its input, what was published for it, and its contacts. Thread-safe.
  void keep(const sensor_msgs::PointCloud2ConstPtr& input, const sensor_msgs::PointCloud2ConstPtr& output,
            const std::vector<TrackedContact>& touching);

private:
  void draw(const ros::TimerEvent&);
  void keepFine(const sensor_msgs::PointCloud2ConstPtr& fine);
  /// The truth of the state stamped `stamp` among the last fine states received: the newest stamped at or
  /// before it, within options.fineStampTolerance (null: none); mutex_ held.
  sensor_msgs::PointCloud2ConstPtr fineAt(const ros::Time& stamp) const;

  ros::CallbackQueue queue_;  // the timer's and fine_state's; declared before them, which remove themselves from it
  ros::Publisher publisher_;
  ros::Timer timer_;
  ros::Subscriber fineSubscriber_;
  MarkerOptions options_;
  RestLookup rest_;
  Reject reject_;
  std::mutex mutex_;  // guards the kept state below
  sensor_msgs::PointCloud2ConstPtr input_, output_;
  std::vector<TrackedContact> touching_;
  std::deque<sensor_msgs::PointCloud2ConstPtr> fine_;  // the newest last
  std::unique_ptr<ros::AsyncSpinner> spinner_;
};

}  // namespace deformation_enrichment::ros_layer
