#include "deformation_enrichment/enrichment/input_memo.hpp"

#include <algorithm>
#include <cstring>

namespace deformation_enrichment::enrichment {
namespace {

bool sameContact(const Contact& a, const Contact& b) {
  return a.point == b.point && a.restState == b.restState && a.normal == b.normal && a.toolId == b.toolId &&
         a.previousFrameAxis == b.previousFrameAxis && a.releasedMagnitude == b.releasedMagnitude;
}

}  // namespace

void InputMemo::remember(const Eigen::Matrix3Xf& positions, std::vector<Contact> contacts, std::uint64_t configVersion,
                         std::uint64_t restVersion) {
  valid_ = true;
  positions_ = positions;
  contacts_ = std::move(contacts);
  configVersion_ = configVersion;
  restVersion_ = restVersion;
}

bool InputMemo::matches(const Eigen::Matrix3Xf& positions, const std::vector<Contact>& contacts, std::uint64_t configVersion,
                        std::uint64_t restVersion) const {
  if (!valid_ || configVersion != configVersion_ || restVersion != restVersion_) return false;
  if (contacts.size() != contacts_.size() || !std::equal(contacts.begin(), contacts.end(), contacts_.begin(), sameContact))
    return false;
  // One pass over the buffer (~0.1 ms per 100k points), far below describing, blending and mapping.
  return positions.cols() == positions_.cols() &&
         std::memcmp(positions.data(), positions_.data(), sizeof(float) * static_cast<std::size_t>(positions.size())) == 0;
}

}  // namespace deformation_enrichment::enrichment
