#pragma once
// Messages a publisher numbered but a subscriber never got: dropped from a full queue on the way. roscpp
// numbers every message it serializes (header.seq, one counter per topic and publishing node), so a jump in
// the numbers of one publisher is the count of messages lost between them. A number that goes back starts
// over (the publisher restarted). Messages passed within one process (nodelets) are not numbered by roscpp:
// whatever the publisher set is taken as it is, so a constant number counts nothing.
#include <cstdint>
#include <map>
#include <string>

namespace deformation_enrichment::ros_layer {

class SequenceGaps {
public:
  /// Records message `seq` of `publisher`; returns how many of its messages are missing just before it.
  std::uint64_t observe(const std::string& publisher, std::uint32_t seq);
  /// Missing messages so far, all publishers together.
  std::uint64_t total() const { return total_; }

private:
  std::map<std::string, std::uint32_t> last_;  // by publisher: the last number seen
  std::uint64_t total_ = 0;
};

}  // namespace deformation_enrichment::ros_layer
