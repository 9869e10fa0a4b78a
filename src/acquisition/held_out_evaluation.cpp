#include "deformation_enrichment/acquisition/held_out_evaluation.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/root_mean_square.hpp"

namespace deformation_enrichment::acquisition {
namespace {

// The displacement e on `vertices` (ascending ids) of an enrichment (ascending ids), zero where it adds none.
Eigen::Matrix3Xd onVertices(const enrichment::SurfaceEnrichment& e, const std::vector<int>& vertices) {
  Eigen::Matrix3Xd out = Eigen::Matrix3Xd::Zero(3, static_cast<Eigen::Index>(vertices.size()));
  std::size_t k = 0;
  for (std::size_t j = 0; j < vertices.size(); ++j) {
    while (k < e.vertices.size() && e.vertices[k] < vertices[j]) ++k;
    if (k < e.vertices.size() && e.vertices[k] == vertices[j]) out.col(static_cast<Eigen::Index>(j)) = e.displacements.col(static_cast<Eigen::Index>(k));
  }
  return out;
}

// The oracle's and the own stamp's RMS on one case: `missing` = fine - coarse on the scored vertices.
void bounds(enrichment::ContactEnricher& enricher, const HeldOutCase& c, const enrichment::ContactDescription& d,
            const std::vector<int>& vertices, const Eigen::Matrix3Xd& missing, ContactScore& s) {
  enrichment::SurfaceEnrichment placed;
  enricher.placeStamp(d, c.ownStamp, c.ownStampRadius, c.ownStampLayers, placed);
  s.ownStampRms = rootMeanSquare(missing - onVertices(placed, vertices));
  const std::vector<cv::Mat>& stamps = enricher.blender()->stamps();
  Eigen::MatrixXd E(missing.size(), static_cast<Eigen::Index>(stamps.size()));
  for (std::size_t i = 0; i < stamps.size(); ++i) {
    enricher.placeStamp(d, stamps[i], enricher.blender()->stampRadius(), enricher.blender()->stampLayers(), placed);
    E.col(static_cast<Eigen::Index>(i)) = onVertices(placed, vertices).reshaped();
  }
  const Eigen::VectorXd target = missing.reshaped();
  const Eigen::VectorXd w = E.completeOrthogonalDecomposition().solve(target);  // least squares, rank-safe
  s.oracleRms = std::sqrt((target - E * w).squaredNorm() / static_cast<double>(vertices.size()));
}

template <typename Ratio>
double meanOver(const std::vector<ContactScore>& contacts, Ratio ratio) {
  double sum = 0.0;
  int n = 0;
  for (const ContactScore& c : contacts)
    if (c.coarseRms > 0.0) sum += ratio(c), ++n;
  return n ? sum / n : 0.0;
}

}  // namespace

std::vector<HeldOutCase> simulateHeldOut(SceneAcquisition& acquisition, const std::vector<PlanEntry>& entries,
                                         const std::function<void(std::size_t)>& progress, const RecordedCoarse* coarse) {
  std::vector<HeldOutCase> cases;
  for (std::size_t i = 0; i < entries.size(); ++i) {  // every entry checked before the first solve
    cases.push_back({entries[i], acquisition.contactOf(entries[i]), {}, {}, 0.0, 1});
    if (coarse && !coarse->settled.count(i))
      throw InvalidInputError("held-out interaction " + std::to_string(i + 1) + " has no settled coarse state in " + coarse->path);
  }
  for (std::size_t i = 0; i < entries.size(); ++i) {
    if (progress) progress(i);
    cases[i].result = coarse ? acquisition.simulate(entries[i], coarse->settled.at(i)) : acquisition.simulate(entries[i]);
    const examples::Example own = acquisition.makeExample(entries[i], cases[i].result);
    cases[i].ownStamp = own.stamp;
    cases[i].ownStampRadius = own.stampRadius;
    cases[i].ownStampLayers = own.stampLayers;
  }
  return cases;
}

double ContactScore::ratioAtGain(double factor) const {
  return std::sqrt(std::max(0.0, 1.0 - 2.0 * factor * detailAlong + factor * factor * detailSize));
}

double ContactScore::bestGain() const { return detailSize > 0.0 ? std::max(0.0, detailAlong / detailSize) : 0.0; }

double HeldOutScore::meanRatio() const { return meanOver(contacts, [](const ContactScore& c) { return c.enrichedRms / c.coarseRms; }); }
double HeldOutScore::meanOracleRatio() const { return meanOver(contacts, [](const ContactScore& c) { return c.oracleRms / c.coarseRms; }); }
double HeldOutScore::meanOwnStampRatio() const {
  return meanOver(contacts, [](const ContactScore& c) { return c.ownStampRms / c.coarseRms; });
}
double HeldOutScore::meanRatioAtGain(double factor) const {
  return meanOver(contacts, [factor](const ContactScore& c) { return c.ratioAtGain(factor); });
}

double HeldOutScore::worstRatio() const {
  double worst = 0.0;
  for (const ContactScore& c : contacts) worst = std::max(worst, c.ratio());
  return worst;
}

double HeldOutScore::worstRatioAtGain(double factor) const {
  double worst = 0.0;
  for (const ContactScore& c : contacts)
    if (c.coarseRms > 0.0) worst = std::max(worst, c.ratioAtGain(factor));
  return worst;
}

double HeldOutScore::bestGain() const {
  double along = 0.0, size = 0.0;
  for (const ContactScore& c : contacts) along += c.detailAlong, size += c.detailSize;
  return size > 0.0 ? std::max(0.0, along / size) : 0.0;
}

double HeldOutScore::medianSecondsPerFrame() const {
  std::vector<double> seconds;
  for (const ContactScore& c : contacts) seconds.push_back(c.timings.totalSeconds);
  if (seconds.empty()) return 0.0;
  std::nth_element(seconds.begin(), seconds.begin() + static_cast<long>(seconds.size() / 2), seconds.end());
  return seconds[seconds.size() / 2];
}

HeldOutScore scoreHeldOut(enrichment::ContactEnricher& enricher, const std::vector<HeldOutCase>& cases, int repetitions,
                          Bounds withBounds) {
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
    std::vector<int> vertices;
    for (Eigen::Index v = 0; v < rest.cols(); ++v)
      if ((rest.col(v) - c.contact.point).norm() < R) vertices.push_back(static_cast<int>(v));
    const Eigen::Matrix3Xd missing = c.result.fine(Eigen::all, vertices) - c.result.coarseOnFine(Eigen::all, vertices);
    const Eigen::Matrix3Xd detail = onVertices(result.enrichment, vertices);
    const Eigen::Matrix3Xd left = missing - detail;
    ContactScore s;
    s.vertices = static_cast<long>(vertices.size());
    s.coarseRms = rootMeanSquare(missing);
    s.enrichedRms = rootMeanSquare(left);
    s.coarseMax = s.vertices ? missing.colwise().norm().maxCoeff() : 0.0;
    s.enrichedMax = s.vertices ? left.colwise().norm().maxCoeff() : 0.0;
    if (const double missingSq = missing.squaredNorm(); missingSq > 0.0) {
      s.detailAlong = detail.cwiseProduct(missing).sum() / missingSq;
      s.detailSize = detail.squaredNorm() / missingSq;
    }
    s.outcome = result.contacts.at(0);
    s.timings = result.timings;
    if (withBounds == Bounds::Compute && s.vertices > 0) bounds(enricher, c, s.outcome.description, vertices, missing, s);
    coarseSq += missing.squaredNorm();
    enrichedSq += left.squaredNorm();
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
