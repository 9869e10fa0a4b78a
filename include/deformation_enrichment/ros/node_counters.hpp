#pragma once
// What the enrichment node counts for /diagnostics: mesh states in and out, every dropped input under its
// input and reason (logged, throttled per input and reason), states lost in the queues before the callback,
// and the compute time per state. Thread-safe: drops are counted from any callback thread.
#include <diagnostic_updater/diagnostic_updater.h>
#include <ros/time.h>

#include <cstdint>
#include <map>
#include <mutex>
#include <string>

#include "deformation_enrichment/ros/sequence_gaps.hpp"

namespace deformation_enrichment::ros_layer {

class NodeCounters {
public:
  /// `errorThrottle`: seconds between two logs of one input and reason.
  explicit NodeCounters(double errorThrottle) : errorThrottle_(errorThrottle) {}

  /// Counts a dropped input under "input: reason" (a short fixed label, one diagnostics entry each),
  /// remembers `detail` as the last error and logs it.
  void drop(const std::string& input, const std::string& reason, const std::string& detail);
  /// A mesh state arrived: message `seq` of `publisher`.
  void stateIn(const std::string& publisher, std::uint32_t seq);
  /// An enriched state went out after `computeMs` of work.
  void stateOut(double computeMs);

  /// The summary (waiting / inputs dropped / enriching) and the counters.
  void report(diagnostic_updater::DiagnosticStatusWrapper& status, bool waitingForRest) const;

private:
  double errorThrottle_;
  mutable std::mutex mutex_;  // guards everything below
  std::uint64_t statesIn_ = 0, statesOut_ = 0;
  std::map<std::string, std::uint64_t> dropped_;  // by "input: reason"
  SequenceGaps statesLost_;
  std::string lastError_;
  double lastComputeMs_ = 0.0, maxComputeMs_ = 0.0;
  std::map<std::string, ros::WallTime> lastLogged_;
};

}  // namespace deformation_enrichment::ros_layer
