#include "deformation_enrichment/ros/sequence_gaps.hpp"

namespace deformation_enrichment::ros_layer {

std::uint64_t SequenceGaps::observe(const std::string& publisher, std::uint32_t seq) {
  const auto [last, first] = last_.try_emplace(publisher, seq);
  if (first) return 0;
  const std::uint32_t previous = last->second;
  last->second = seq;
  if (seq <= previous) return 0;  // the same number (not numbered) or a restart
  const std::uint64_t missing = seq - previous - 1;
  total_ += missing;
  return missing;
}

}  // namespace deformation_enrichment::ros_layer
