#include "deformation_enrichment/acquisition/held_out_evaluation.hpp"

#include <algorithm>
#include <cmath>

#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::acquisition {

std::vector<HeldOutCase> simulateHeldOut(const SceneAcquisition& acquisition, const std::vector<PlanEntry>& entries,
                                         const std::function<void(std::size_t)>& progress) {
  std::vector<HeldOutCase> cases;
  for (std::size_t i = 0; i < entries.size(); ++i)  // every entry checked before the first solve
    cases.push_back({entries[i], acquisition.contactOf(entries[i]), {}});
  for (std::size_t i = 0; i < entries.size(); ++i) {
    if (progress) progress(i);
    cases[i].result = acquisition.simulate(entries[i]);
  }
  return cases;
}

HeldOutScore scoreHeldOut(enrichment::ContactEnricher& enricher, const std::vector<HeldOutCase>& cases, int repetitions) {
  if (!enricher.hasExamples()) throw InvalidInputError("scoreHeldOut: the enricher has no example set");
  if (cases.empty()) throw InvalidInputError("scoreHeldOut: no held-out case");
  if (repetitions < 1) throw InvalidInputError("scoreHeldOut: repetitions must be >= 1");
  const Eigen::Matrix3Xd& rest = enricher.restSurface().vertices;
  const double R = enricher.options().stampRadius;
  HeldOutScore score;
  double coarseSq = 0.0, enrichedSq = 0.0;
  long count = 0;
  for (const HeldOutCase& c : cases) {
    std::vector<enrichment::EnrichmentResult> runs(static_cast<std::size_t>(repetitions));
    for (auto& run : runs) enricher.enrich(c.result.coarseOnFine, {c.contact}, run);
    std::nth_element(runs.begin(), runs.begin() + repetitions / 2, runs.end(), [](const auto& a, const auto& b) {
      return a.timings.totalSeconds < b.timings.totalSeconds;
    });
    const enrichment::EnrichmentResult& result = runs[static_cast<std::size_t>(repetitions / 2)];
    Eigen::Matrix3Xd enriched = c.result.coarseOnFine;
    enricher.apply(result, enriched);
    ContactScore s;
    double cSq = 0.0, eSq = 0.0;
    for (Eigen::Index v = 0; v < rest.cols(); ++v) {
      if ((rest.col(v) - c.contact.point).norm() >= R) continue;
      const double ce = (c.result.coarseOnFine.col(v) - c.result.fine.col(v)).norm();
      const double ee = (enriched.col(v) - c.result.fine.col(v)).norm();
      cSq += ce * ce;
      eSq += ee * ee;
      s.coarseMax = std::max(s.coarseMax, ce);
      s.enrichedMax = std::max(s.enrichedMax, ee);
      ++s.vertices;
    }
    if (s.vertices > 0) {
      s.coarseRms = std::sqrt(cSq / s.vertices);
      s.enrichedRms = std::sqrt(eSq / s.vertices);
    }
    s.outcome = result.contacts.at(0);
    s.timings = result.timings;
    coarseSq += cSq;
    enrichedSq += eSq;
    count += s.vertices;
    score.coarseMax = std::max(score.coarseMax, s.coarseMax);
    score.enrichedMax = std::max(score.enrichedMax, s.enrichedMax);
    score.secondsPerFrame += result.timings.totalSeconds / static_cast<double>(cases.size());
    score.contacts.push_back(std::move(s));
  }
  if (count > 0) {
    score.coarseRms = std::sqrt(coarseSq / count);
    score.enrichedRms = std::sqrt(enrichedSq / count);
  }
  return score;
}

}  // namespace deformation_enrichment::acquisition
