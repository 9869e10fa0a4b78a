#include "deformation_enrichment/ros/node_counters.hpp"

#include <ros/console.h>

#include <algorithm>

namespace deformation_enrichment::ros_layer {

void NodeCounters::drop(const std::string& input, const std::string& reason, const std::string& detail) {
  const std::string key = input + ": " + reason;
  std::lock_guard<std::mutex> lock(mutex_);
  ++dropped_[key];
  lastError_ = key + " (" + detail + ")";
  const ros::WallTime now = ros::WallTime::now();
  ros::WallTime& last = lastLogged_[key];
  if (last.isZero() || (now - last).toSec() >= errorThrottle_) {
    last = now;
    ROS_ERROR("dropped %s: %s: %s (keeping the last good state)", input.c_str(), reason.c_str(), detail.c_str());
  }
}

void NodeCounters::stateIn(const std::string& publisher, std::uint32_t seq) {
  std::lock_guard<std::mutex> lock(mutex_);
  ++statesIn_;
  statesLost_.observe(publisher, seq);
}

void NodeCounters::stateOut(double computeMs) {
  std::lock_guard<std::mutex> lock(mutex_);
  ++statesOut_;
  lastComputeMs_ = computeMs;
  maxComputeMs_ = std::max(maxComputeMs_, computeMs);
}

void NodeCounters::report(diagnostic_updater::DiagnosticStatusWrapper& status, bool waitingForRest) const {
  std::lock_guard<std::mutex> lock(mutex_);
  std::uint64_t droppedTotal = 0;
  for (const auto& [inputAndReason, count] : dropped_) {
    status.add("dropped " + inputAndReason, count);
    droppedTotal += count;
  }
  if (waitingForRest) {
    status.summary(diagnostic_msgs::DiagnosticStatus::WARN, "waiting for a rest mesh");
  } else if (droppedTotal > 0) {
    status.summary(diagnostic_msgs::DiagnosticStatus::WARN, "inputs dropped; last: " + lastError_);
  } else {
    status.summary(diagnostic_msgs::DiagnosticStatus::OK, "enriching");
  }
  status.add("mesh states in", statesIn_);
  status.add("mesh states lost in the input queue (newer states came first)", statesLost_.total());
  status.add("enriched states out", statesOut_);
  status.add("last compute [ms]", lastComputeMs_);
  status.add("max compute [ms]", maxComputeMs_);
  status.add("last error", lastError_);
}

}  // namespace deformation_enrichment::ros_layer
