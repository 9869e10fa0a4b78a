#include "deformation_enrichment/enrichment/contact_enricher.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include "deformation_enrichment/all_finite.hpp"
#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/seconds_since.hpp"
#include "deformation_enrichment/smooth_ramp.hpp"

namespace deformation_enrichment::enrichment {
namespace {

using Clock = std::chrono::steady_clock;

void checkOptions(const ContactEnricherOptions& o) {
  if (!(o.stampRadius > 0.0) || !std::isfinite(o.stampRadius))
    throw InvalidInputError("contact enricher: stamp radius must be positive and finite");
  if (!(o.descriptors.window.scale > 0.0) || !std::isfinite(o.descriptors.window.scale))
    throw InvalidInputError("contact enricher: window scale h must be positive and finite");
  if (!(o.sampleSpacing >= 0.0) || !std::isfinite(o.sampleSpacing))
    throw InvalidInputError("contact enricher: sample spacing must be >= 0 and finite");
  if (!(o.maxMagnitudeRatio > 0.0) || !(o.maxWeight > 0.0))
    throw InvalidInputError("contact enricher: the magnitude-ratio and weight bounds must be positive (infinity: unbounded)");
  o.gain.check();
}

// min(1, bound / sum_i |w_i|); 1 without a bound. Continuous in the weights, so a stream stays continuous.
double weightNormBound(const Eigen::VectorXd& weights, double bound) {
  const double norm = weights.lpNorm<1>();
  return bound > 0.0 && norm > bound ? bound / norm : 1.0;
}

}  // namespace

ContactEnricher::ContactEnricher(mesh::TriangleMesh restSurface, const ContactEnricherOptions& options,
                                 std::optional<descriptors::PointSampling> siteDensity)
    : options_((checkOptions(options), options)),
      describer_(std::move(restSurface), options.descriptors, options.sampleSpacing, std::move(siteDensity)),
      mapper_(describer_.restSurface().vertices, options.rimBand, describer_.restNormals(), describer_.restSurface().triangles) {}

ContactEnricher::~ContactEnricher() = default;
ContactEnricher::ContactEnricher(ContactEnricher&&) noexcept = default;
ContactEnricher& ContactEnricher::operator=(ContactEnricher&&) noexcept = default;

void ContactEnricher::setExamples(const examples::ExampleSet& set, const ExampleBlenderOptions& blenderOptions) {
  ExampleBlenderOptions o = blenderOptions;
  o.magnitudeAware = options_.magnitudeAware;  // fit the widths for the predictor actually used
  auto blender = std::make_shared<ExampleBlender>(set, o);
  if (std::abs(blender->stampRadius() - options_.stampRadius) > 1e-9 * options_.stampRadius)
    throw InvalidInputError("contact enricher: example stamp radius " + std::to_string(blender->stampRadius()) +
                            " m differs from the configured " + std::to_string(options_.stampRadius) + " m");
  std::vector<cv::Mat> stamps;
  Eigen::VectorXd muNorms(static_cast<Eigen::Index>(set.examples.size()));
  for (std::size_t i = 0; i < set.examples.size(); ++i) {
    stamps.push_back(set.examples[i].stamp.clone());
    muNorms(static_cast<Eigen::Index>(i)) = set.examples[i].mu.values().norm();
  }
  // Only now: a rejected set leaves the previous one active.
  loadedWidths_ = blender->widths();
  blender_ = std::move(blender);
  stamps_ = std::move(stamps);
  muNorms_ = std::move(muNorms);
}

void DetailGain::check() const {
  if (!(stampGain >= 0.0) || !std::isfinite(stampGain)) throw InvalidInputError("stamp gain must be >= 0 and finite");
  if (!(minConfidence >= 0.0 && minConfidence <= 1.0)) throw InvalidInputError("minimum confidence must be in [0, 1]");
  if (!(maxWeightNorm >= 0.0) || !std::isfinite(maxWeightNorm))
    throw InvalidInputError("maximum weight norm must be >= 0 and finite (0: no bound)");
}

DetailGain DetailGain::withStampGainTimes(double factor) const {
  DetailGain scaled = *this;
  scaled.stampGain *= factor;
  return scaled;
}

void ContactEnricher::setDetailGain(const DetailGain& gain) {
  gain.check();
  options_.gain = gain;
}

void ContactEnricher::setKernelWidths(double sigmaRho, double sigmaU) {
  if (!blender_) throw InvalidInputError("contact enricher: no example set loaded to set kernel widths for");
  if (!std::isfinite(sigmaRho) || !std::isfinite(sigmaU)) throw InvalidInputError("contact enricher: kernel widths must be finite");
  KernelWidths widths = loadedWidths_;
  if (sigmaRho > 0.0) widths.sigmaRho = sigmaRho;
  if (sigmaU > 0.0) widths.sigmaU = sigmaU;
  blender_->setWidths(widths);
}

template <typename Positions>
void ContactEnricher::checkState(const Positions& current, StateCheck check) const {
  if (current.cols() != size())
    throw InvalidInputError("contact enricher: " + std::to_string(current.cols()) + " current positions for " +
                            std::to_string(size()) + " surface vertices");
  if (check == StateCheck::Full && !allFiniteValues(current)) throw InvalidInputError("contact enricher: non-finite current surface positions");
}

ContactDescription ContactEnricher::describe(const Eigen::Matrix3Xd& current, const Contact& contact) const {
  checkState(current);
  return describer_.describe(current, contact);
}

void ContactEnricher::blendContact(const Contact& contact, ContactOutcome& outcome, ContactStamp& stamp) {
  blender_->blend(outcome.description.rho, outcome.description.mu, blendScratch_);  // eq. 15 -> RBF -> eq. 16
  outcome.weights = blendScratch_.rbf.weights;
  outcome.confidence = blendScratch_.rbf.confidence;
  outcome.muNorm = outcome.description.mu.values().norm();
  Eigen::VectorXd effective;
  double weightNormScale = 1.0;
  const bool followsMagnitude = options_.magnitudeAware || blender_->method() == BlendMethod::Regression;
  if (blender_->method() == BlendMethod::Regression) {
    // The regression is linear in mu: beyond maxMagnitudeRatio times the largest example it stops growing.
    const double reach = options_.maxMagnitudeRatio * blender_->largestMuNorm();
    effective = outcome.weights * (outcome.muNorm > reach ? reach / outcome.muNorm : 1.0);
    weightNormScale = weightNormBound(outcome.weights, options_.gain.maxWeightNorm);
  } else {
    // Psi = sum_i w~_i (|mu| / |mu[i]|) Psi[i] when magnitude-aware (examples without deformation, |mu[i]| = 0,
    // contribute nothing), with w~_i and the ratio clamped (options).
    effective = outcome.weights.cwiseMax(-options_.maxWeight).cwiseMin(options_.maxWeight);
    if (options_.magnitudeAware)
      for (Eigen::Index i = 0; i < effective.size(); ++i)
        effective(i) = muNorms_(i) > 0.0 ? effective(i) * std::min(outcome.muNorm / muNorms_(i), options_.maxMagnitudeRatio) : 0.0;
  }
  outcome.detailScale = smoothRamp(outcome.confidence, options_.gain.minConfidence) * weightNormScale;
  if (contact.releasedMagnitude > 0.0 && !followsMagnitude)
    outcome.detailScale *= std::min(1.0, outcome.muNorm / contact.releasedMagnitude);
  if (effective != outcome.weights) blendScratch_.stamp = blendStamps(stamps_, effective);
  stamp.contact = outcome.description.p;
  stamp.frame = outcome.description.B;
  stamp.rotation = outcome.description.R;
  stamp.radius = blender_->stampRadius();
  stamp.layers = blender_->stampLayers();
  const double scale = options_.gain.stampGain * outcome.detailScale;
  if (scale == 1.0) blendScratch_.stamp.copyTo(stamp.stamp);
  else blendScratch_.stamp.convertTo(stamp.stamp, -1, scale);
}

void ContactEnricher::enrich(const Eigen::Matrix3Xd& current, const std::vector<Contact>& contacts, EnrichmentResult& out,
                             StateCheck check) {
  enrichState(current, contacts, out, check);
}

void ContactEnricher::enrich(const Eigen::Matrix3Xf& current, const std::vector<Contact>& contacts, EnrichmentResult& out,
                             StateCheck check) {
  enrichState(current, contacts, out, check);
}

void ContactEnricher::placeStamp(const ContactDescription& description, const cv::Mat& stamp, double radius, int layers,
                                 SurfaceEnrichment& out) {
  // A list of its own, not stampScratch_: the blend writes into stampScratch_'s stamps, and cv::Mat shares
  // its data on assignment, so a later enrich() would overwrite the caller's stamp (a set's own, say).
  std::vector<ContactStamp> placed(1);
  placed[0].contact = description.p;
  placed[0].frame = description.B;
  placed[0].rotation = description.R;
  placed[0].stamp = stamp;
  placed[0].radius = radius;
  placed[0].layers = layers;
  mapper_.map(placed, out);
}

template <typename Positions>
void ContactEnricher::enrichState(const Positions& current, const std::vector<Contact>& contacts, EnrichmentResult& out,
                                  StateCheck check) {
  const auto start = Clock::now();
  out.contacts.clear();
  out.timings = EnrichmentTimings();
  out.enrichment.vertices.clear();
  out.enrichment.displacements.resize(3, 0);
  if (contacts.empty()) return;  // nothing touches the surface: no descriptor, blend or mapping work
  if (!blender_) throw InvalidInputError("contact enricher: no example set loaded");
  checkState(current, check);
  stampScratch_.resize(contacts.size());
  for (std::size_t c = 0; c < contacts.size(); ++c) {
    auto t0 = Clock::now();
    ContactOutcome outcome;
    outcome.toolId = contacts[c].toolId;
    outcome.description = describer_.describe(current, contacts[c]);  // the state was checked once above
    out.timings.descriptorSeconds += secondsSince(t0);
    t0 = Clock::now();
    blendContact(contacts[c], outcome, stampScratch_[c]);
    out.timings.blendSeconds += secondsSince(t0);
    out.contacts.push_back(std::move(outcome));
  }
  const auto t0 = Clock::now();
  mapper_.map(stampScratch_, out.enrichment);  // eq. (1) with the multi-contact rim rule
  out.timings.mapSeconds = secondsSince(t0);
  out.timings.totalSeconds = secondsSince(start);
}

}  // namespace deformation_enrichment::enrichment
