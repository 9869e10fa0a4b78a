#pragma once
// Held-out accuracy of the enrichment: for interactions that are not in the example set, the
// fine simulation is the ground truth. The coarse state (carried onto the fine surface) is enriched with
// the example set and both are compared with the fine state over the fine surface vertices within the
// stamp radius of the contact. Simulation is separate from scoring so that one set of expensive fine
// solves scores many run-time variants (example count, stamp resolution, Hermite order).
#include <functional>
#include <vector>

#include "deformation_enrichment/acquisition/scene_acquisition.hpp"
#include "deformation_enrichment/enrichment/contact_enricher.hpp"

namespace deformation_enrichment::acquisition {

struct HeldOutCase {
  PlanEntry entry;
  enrichment::Contact contact;  ///< where the tool meets the surface (rest state)
  InteractionResult result;
};

/// Coarse and fine solves of every entry (all entries are checked first); `progress(i)` (optional) is
/// called before entry i.
std::vector<HeldOutCase> simulateHeldOut(const SceneAcquisition& acquisition, const std::vector<PlanEntry>& entries,
                                         const std::function<void(std::size_t)>& progress = {});

struct ContactScore {
  long vertices = 0;  ///< fine surface vertices within the stamp radius
  double coarseRms = 0.0, enrichedRms = 0.0, coarseMax = 0.0, enrichedMax = 0.0;  ///< metres
  enrichment::ContactOutcome outcome;   ///< descriptors, weights, confidence
  enrichment::EnrichmentTimings timings;  ///< of the median-time repetition
};

struct HeldOutScore {
  std::vector<ContactScore> contacts;
  double coarseRms = 0.0, enrichedRms = 0.0, coarseMax = 0.0, enrichedMax = 0.0;  ///< over all contacts' vertices
  double secondsPerFrame = 0.0;  ///< mean over contacts of the median enrichment time
  double ratio() const { return coarseRms > 0.0 ? enrichedRms / coarseRms : 0.0; }
};

/// Enriches every case with `enricher` (examples already set, built on the acquisition's display surface)
/// and scores it. Each enrichment runs `repetitions` times (>= 1) for a median compute time. Throws
/// InvalidInputError when the enricher has no examples or no case is given.
HeldOutScore scoreHeldOut(enrichment::ContactEnricher& enricher, const std::vector<HeldOutCase>& cases, int repetitions = 1);

}  // namespace deformation_enrichment::acquisition
