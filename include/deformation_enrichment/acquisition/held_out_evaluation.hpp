#pragma once
// Held-out accuracy of the enrichment: for interactions that are not in the example set, the
// fine simulation is the ground truth. The coarse state (carried onto the fine surface) is enriched with
// the example set and both are compared with the fine state over the fine surface vertices within the
// stamp radius of the contact. Simulation is separate from scoring so that one set of expensive fine
// solves scores many run-time variants (example count, blend, stamp resolution, Hermite order).
//
// Two bounds put a score in context, both on the same vertices:
//   - the oracle: the least-squares blend of the set's stamps given the truth, min_w |fine - coarse - sum_i
//     w_i e_i| with e_i stamp i placed at the contact (eq. 1). No blend of these stamps does better.
//   - the own stamp: the stamp an example at exactly this interaction would carry, placed at the contact;
//     what remains is what the stamp representation and the rim fade lose, however good the blend.
// And one factor on the detail given the truth: with m = fine - coarse and d the added detail on a contact's
// vertices, its ratio at a factor g on d is sqrt(1 - 2 g <d, m> / |m|^2 + g^2 |d|^2 / |m|^2), and the g with
// the least sum of squared per-contact ratios is sum_c <d, m>_c / |m_c|^2 over sum_c |d_c|^2 / |m_c|^2, or 0
// where that is negative (a stamp gain is >= 0): how far the stamp gain is from the best one (a transfer's
// material scale, the regression's shrinkage).
#include <functional>
#include <opencv2/core.hpp>
#include <vector>

#include "deformation_enrichment/acquisition/scene_acquisition.hpp"
#include "deformation_enrichment/enrichment/contact_enricher.hpp"

namespace deformation_enrichment::acquisition {

struct HeldOutCase {
  PlanEntry entry;
  enrichment::Contact contact;  ///< where the tool meets the surface (rest state)
  InteractionResult result;
  cv::Mat ownStamp;             ///< the stamp of this interaction's own example (the acquisition's settings)
  double ownStampRadius = 0.0;
  int ownStampLayers = 1;
};

/// Coarse and fine solves of every entry (all entries are checked first) and their own stamps;
/// `progress(i)` (optional) is called before entry i. With `coarse` (entries = its plan), the coarse half
/// of entry i is its recorded settled state; an entry without one is refused before any solve.
std::vector<HeldOutCase> simulateHeldOut(SceneAcquisition& acquisition, const std::vector<PlanEntry>& entries,
                                         const std::function<void(std::size_t)>& progress = {},
                                         const RecordedCoarse* coarse = nullptr);

struct ContactScore {
  long vertices = 0;  ///< fine surface vertices within the stamp radius
  double coarseRms = 0.0, enrichedRms = 0.0, coarseMax = 0.0, enrichedMax = 0.0;  ///< metres
  double oracleRms = 0.0, ownStampRms = 0.0;  ///< the bounds above (metres), when asked for
  double detailAlong = 0.0, detailSize = 0.0;  ///< <d, m> / |m|^2 and |d|^2 / |m|^2 (0 without coarse error)
  enrichment::ContactOutcome outcome;   ///< descriptors, weights, confidence
  enrichment::EnrichmentTimings timings;  ///< of the median-time repetition
  double ratio() const { return coarseRms > 0.0 ? enrichedRms / coarseRms : 0.0; }
  /// The ratio with the detail scaled by `factor` (ratio() at 1, up to round-off).
  double ratioAtGain(double factor) const;
  /// This contact's best factor (see above); 0 without detail.
  double bestGain() const;
};

struct HeldOutScore {
  std::vector<ContactScore> contacts;
  double coarseRms = 0.0, enrichedRms = 0.0, coarseMax = 0.0, enrichedMax = 0.0;  ///< over all contacts' vertices
  double secondsPerFrame = 0.0;  ///< mean over contacts of the median enrichment time
  double ratio() const { return coarseRms > 0.0 ? enrichedRms / coarseRms : 0.0; }
  /// Mean and largest of the per-contact ratios (contacts without coarse error left out).
  double meanRatio() const;
  double worstRatio() const;
  /// Mean per-contact ratio of the oracle and of the own stamp.
  double meanOracleRatio() const;
  double meanOwnStampRatio() const;
  /// The factor on the detail with the least sum of squared per-contact ratios (see above); 0 when no
  /// contact got detail or the detail points away from the truth. The mean and largest per-contact ratio at
  /// a factor.
  double bestGain() const;
  double meanRatioAtGain(double factor) const;
  double worstRatioAtGain(double factor) const;
  /// Median over contacts of the median enrichment time.
  double medianSecondsPerFrame() const;
};

enum class Bounds { None, Compute };

/// Enriches every case with `enricher` (examples already set, built on the acquisition's display surface)
/// and scores it. Each enrichment runs `repetitions` times (>= 1) for a median compute time. With
/// Bounds::Compute also the oracle and own-stamp errors. Throws InvalidInputError when the enricher has no
/// examples or no case is given.
HeldOutScore scoreHeldOut(enrichment::ContactEnricher& enricher, const std::vector<HeldOutCase>& cases, int repetitions = 1,
                          Bounds bounds = Bounds::None);

}  // namespace deformation_enrichment::acquisition
