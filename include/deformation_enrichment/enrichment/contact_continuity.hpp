#pragma once
// Temporal coherence of a live stream's contacts (docs/design.md §4, "a stream that holds still"): each
// tool's stamping frame starts from its previous b_x (ContactEnricher's last resort, so B does not jump
// where the rules have no direction), and when a tool lifts off, the tissue it released keeps its detail:
// the rest point it last touched becomes a released site, enriched while its deformation descriptor says the
// tissue is still deformed and fading with |mu| as the coarse state relaxes, until |mu| falls below a
// fraction of its value at lift-off or a tool touches it again (then its contact takes over). Memories go
// with where the tissue is touched, not with tool ids: a contact takes the memory of the nearest site within
// the match radius, so two tools that swap ids (or one tool's id changing) do not swap frames.
#include <map>
#include <vector>

#include "deformation_enrichment/enrichment/contact_enricher.hpp"

namespace deformation_enrichment::enrichment {

struct ContactContinuityOptions {
  bool followRelease = true;  ///< keep released sites (false: detail ends with the contact)
  /// A released site is dropped once |mu| there falls below this fraction of |mu| at lift-off.
  double releaseFloor = 0.02;
  /// A contact continues the site (tool or released) whose last contact point is nearest to it within this
  /// distance [m] (points compared as given: current-state points for tools in contact); farther, it starts
  /// afresh and the old site is released.
  double matchRadius = 0.005;
};

class ContactContinuity {
public:
  /// Throws InvalidInputError for a release floor outside [0, 1) or a match radius not positive and finite.
  explicit ContactContinuity(const ContactContinuityOptions& options = {});

  /// The contacts to enrich this frame: `touching` (each tool in contact now, distinct tool ids), each with
  /// the previous frame axis of the site it continues (nearest first, one contact per site), then the
  /// released sites no contact continues. Throws InvalidInputError for duplicate tool ids (nothing changes).
  std::vector<Contact> contactsFor(const std::vector<Contact>& touching);
  /// Records what ContactEnricher::enrich made of the last contactsFor(): rest points, frames, |mu|.
  /// A frame that was not enriched (an error) is simply not recorded.
  void update(const EnrichmentResult& result);
  /// Forgets every tool (a new rest mesh, a stream that started over).
  void reset() {
    memory_.clear();
    touchedPoints_.clear();
  }
  std::size_t releasedSites() const;

private:
  struct Memory {
    Eigen::Vector3d restPoint = Eigen::Vector3d::Zero();
    Eigen::Vector3d lastPoint = Eigen::Vector3d::Zero();  ///< the contact's point as given, last time touched
    Eigen::Vector3d frameAxis = Eigen::Vector3d::UnitX();
    double muNorm = 0.0;             ///< |mu| on the last enriched frame
    double releasedMagnitude = 0.0;  ///< > 0 while released: |mu| at lift-off
  };
  /// Re-keys memory_ so that each touching contact's id holds the memory of the site it continues.
  void matchSites(const std::vector<Contact>& touching);

  ContactContinuityOptions options_;
  std::map<int, Memory> memory_;  // by tool id (released sites no tool continues: any unused id)
  std::map<int, Eigen::Vector3d> touchedPoints_;  // the last contactsFor()'s touching points, by tool id
};

}  // namespace deformation_enrichment::enrichment
