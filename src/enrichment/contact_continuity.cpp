#include "deformation_enrichment/enrichment/contact_continuity.hpp"

#include <set>
#include <string>

#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::enrichment {

ContactContinuity::ContactContinuity(const ContactContinuityOptions& options) : options_(options) {
  if (!(options.releaseFloor >= 0.0 && options.releaseFloor < 1.0))
    throw InvalidInputError("contact continuity: release floor must be in [0, 1)");
}

std::vector<Contact> ContactContinuity::contactsFor(const std::vector<Contact>& touching) {
  std::set<int> ids;
  for (const Contact& c : touching)
    if (!ids.insert(c.toolId).second)
      throw InvalidInputError("contact continuity: tool id " + std::to_string(c.toolId) + " touches twice in one frame");
  std::vector<Contact> contacts = touching;
  for (Contact& c : contacts) {
    const auto it = memory_.find(c.toolId);
    if (it == memory_.end()) continue;
    if (!c.previousFrameAxis) c.previousFrameAxis = it->second.frameAxis;
    it->second.releasedMagnitude = 0.0;  // touching again: its contact takes over
  }
  for (auto it = memory_.begin(); it != memory_.end();) {
    Memory& m = it->second;
    if (ids.count(it->first)) {
      ++it;
      continue;
    }
    if (m.releasedMagnitude == 0.0) m.releasedMagnitude = m.muNorm;  // lifted off since the last frame
    if (!options_.followRelease || !(m.releasedMagnitude > 0.0)) {   // nothing deformed to follow
      it = memory_.erase(it);
      continue;
    }
    Contact site;
    site.point = m.restPoint;
    site.restState = true;
    site.toolId = it->first;
    site.previousFrameAxis = m.frameAxis;
    site.releasedMagnitude = m.releasedMagnitude;
    contacts.push_back(site);
    ++it;
  }
  return contacts;
}

void ContactContinuity::update(const EnrichmentResult& result) {
  for (const ContactOutcome& outcome : result.contacts) {
    Memory& m = memory_[outcome.toolId];
    m.restPoint = outcome.description.p;
    m.frameAxis = outcome.description.B.col(0);
    m.muNorm = outcome.muNorm;
    if (m.releasedMagnitude > 0.0 && outcome.muNorm < options_.releaseFloor * m.releasedMagnitude)
      memory_.erase(outcome.toolId);  // the released tissue is back near rest
  }
}

std::size_t ContactContinuity::releasedSites() const {
  std::size_t n = 0;
  for (const auto& entry : memory_) n += entry.second.releasedMagnitude > 0.0 ? 1 : 0;
  return n;
}

}  // namespace deformation_enrichment::enrichment
