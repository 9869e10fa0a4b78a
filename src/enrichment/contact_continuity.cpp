#include "deformation_enrichment/enrichment/contact_continuity.hpp"

#include <algorithm>
#include <cmath>
#include <set>
#include <string>
#include <tuple>

#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::enrichment {

ContactContinuity::ContactContinuity(const ContactContinuityOptions& options) : options_(options) {
  if (!(options.releaseFloor >= 0.0 && options.releaseFloor < 1.0))
    throw InvalidInputError("contact continuity: release floor must be in [0, 1)");
  if (!(options.matchRadius > 0.0 && std::isfinite(options.matchRadius)))
    throw InvalidInputError("contact continuity: match radius must be positive and finite");
}

void ContactContinuity::matchSites(const std::vector<Contact>& touching) {
  // Closest pairs first (greedy one-to-one assignment; pairs are few: tools times sites).
  std::vector<std::tuple<double, std::size_t, int>> pairs;
  for (std::size_t c = 0; c < touching.size(); ++c)
    for (const auto& [id, m] : memory_) {
      const double distance = (m.lastPoint - touching[c].point).norm();
      if (distance <= options_.matchRadius) pairs.emplace_back(distance, c, id);
    }
  std::sort(pairs.begin(), pairs.end());
  std::set<std::size_t> matched;
  std::set<int> used;
  std::map<int, Memory> rekeyed;
  for (const auto& [distance, c, id] : pairs) {
    if (matched.count(c) || used.count(id)) continue;
    matched.insert(c);
    used.insert(id);
    rekeyed[touching[c].toolId] = memory_[id];
  }
  // Unmatched sites keep their memory under an id no touching tool has, so they are released.
  int spare = -1;
  for (const Contact& c : touching) spare = std::min(spare, c.toolId - 1);
  for (const auto& [id, m] : memory_) {
    if (used.count(id)) continue;
    int key = id;
    while (rekeyed.count(key) || std::any_of(touching.begin(), touching.end(), [&](const Contact& c) { return c.toolId == key; }))
      key = spare--;
    rekeyed[key] = m;
  }
  memory_ = std::move(rekeyed);
}

std::vector<Contact> ContactContinuity::contactsFor(const std::vector<Contact>& touching) {
  std::set<int> ids;
  for (const Contact& c : touching)
    if (!ids.insert(c.toolId).second)
      throw InvalidInputError("contact continuity: tool id " + std::to_string(c.toolId) + " touches twice in one frame");
  matchSites(touching);
  touchedPoints_.clear();
  std::vector<Contact> contacts = touching;
  for (Contact& c : contacts) {
    const auto it = memory_.find(c.toolId);
    touchedPoints_[c.toolId] = c.point;
    if (it == memory_.end()) continue;  // a new site: update() records it
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
    const auto touched = touchedPoints_.find(outcome.toolId);
    if (touched != touchedPoints_.end()) m.lastPoint = touched->second;
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
