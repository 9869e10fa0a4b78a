// The configuration side of EnrichmentSession: example sets and knobs, built on the caller's thread outside
// the frame lock and installed between two states, and what the session reports (diagnostics). Rest surfaces
// are built on the session's worker thread: session_rest_worker.cpp.
#include <cmath>

#include "deformation_enrichment/enrichment/descriptor_order.hpp"
#include "deformation_enrichment/enrichment/enrichment_session.hpp"
#include "deformation_enrichment/enrichment/example_set_options.hpp"
#include "deformation_enrichment/enrichment/material_similarity.hpp"
#include "deformation_enrichment/enrichment/surface_enricher.hpp"
#include "deformation_enrichment/error.hpp"
#include "session_built.hpp"

namespace deformation_enrichment::enrichment {
namespace {

void checkKnobs(const KnobOptions& k) {
  k.gain.check();
  if (!std::isfinite(k.sigmaRho) || !std::isfinite(k.sigmaU)) throw InvalidInputError("kernel widths must be finite");
  if (k.hermiteOrder < 0) throw InvalidInputError("Hermite order must be >= 0 (0: the set's)");
  if (!(k.temporalSmoothing >= 0.0) || !std::isfinite(k.temporalSmoothing))
    throw InvalidInputError("temporal smoothing must be >= 0 and finite");
}

}  // namespace

void EnrichmentSession::log(SessionLogLevel level, const std::string& text) const {
  if (options_.log) options_.log(level, text);
}

std::unique_ptr<EnrichmentSession::Built> EnrichmentSession::build(const RestSurface& rest, const examples::ExampleSet& set,
                                                                   const KnobOptions& knobs) const {
  // Contacts are described exactly as the set's examples were (window, quadrature, interior sampling,
  // orders, stamp radius); the defaults only fill in what a set does not record. A lower mu order may be
  // chosen by knob; the leave-one-out widths are then fitted for the descriptors actually compared.
  ContactEnricherOptions options = optionsFor(set, options_.defaults);
  const int built = options.descriptors.deformationOrder;
  const int order = knobs.hermiteOrder > 0 ? std::min(knobs.hermiteOrder, built) : built;
  options.descriptors.deformationOrder = order;
  auto result = std::make_unique<Built>();
  // The descriptors see geometry only: detail acquired on another material fades with its difference.
  // A calibrated transfer gain replaces that fade for a set of another scene.
  if (options_.scene && set.metadata.provenance) {
    result->materialSimilarity = materialSimilarity(set.metadata.provenance->scene, *options_.scene);
    const bool transfer = set.metadata.provenance->scene.name != options_.scene->name;
    result->stampScale = transfer && options_.transferGain > 0.0 ? options_.transferGain : result->materialSimilarity;
  }
  options.gain = knobs.gain.withStampGainTimes(result->stampScale);
  const mesh::TetMesh* volume = rest.geometry.volume ? &*rest.geometry.volume : nullptr;
  result->enricher = std::make_unique<ContactEnricher>(
      surfaceEnricher(rest.geometry.surface, volume, options, options_.density, &result->siteDensity));
  ExampleBlenderOptions blending = options_.blending;
  blending.method = knobs.blend;
  result->enricher->setExamples(withDeformationOrder(set, order), blending);
  result->enricher->setKernelWidths(knobs.sigmaRho, knobs.sigmaU);
  result->restVersion = rest.version;
  return result;
}

void EnrichmentSession::installConfiguration(std::shared_ptr<const examples::ExampleSet> set, const KnobOptions& knobs) {
  for (;;) {
    std::shared_ptr<const RestSurface> rest;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      rest = active_;
    }
    // Built outside the lock (site density, kernel-width fit): the enrichment goes on meanwhile.
    std::unique_ptr<Built> built = rest ? build(*rest, *set, knobs) : nullptr;
    std::unique_ptr<Built> old;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (active_ != rest) continue;  // the worker installed a new rest surface meanwhile: build for that one
      set_ = std::move(set);
      knobs_ = knobs;
      ++configVersion_;
      if (knobs.temporalSmoothing != temporalFilter_.timeConstant()) temporalFilter_.setTimeConstant(knobs.temporalSmoothing);
      if (built) {
        built->configVersion = configVersion_;
        old = std::move(enricher_);
        enricher_ = std::move(built);
      }
    }
    changed_.notify_all();  // a rest surface being built is built again with this configuration
    return;
  }
}

void EnrichmentSession::setExampleSet(examples::ExampleSet set) {
  if (set.examples.empty()) throw InvalidInputError("example set has no examples");
  const int built = deformationOrder(set);  // throws for examples of different layouts
  const KnobOptions requested = knobs();
  if (requested.hermiteOrder > built)
    log(SessionLogLevel::Warning, "the example set stores deformation moments up to order " + std::to_string(built) +
                                      ": hermite_order " + std::to_string(requested.hermiteOrder) + " runs at " +
                                      std::to_string(built));
  installConfiguration(std::make_shared<const examples::ExampleSet>(std::move(set)), requested);
}

void EnrichmentSession::setKnobs(const KnobOptions& requested) {
  checkKnobs(requested);
  std::shared_ptr<const examples::ExampleSet> set;
  int activeOrder = 0;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    set = set_;
    if (enricher_ && enricher_->enricher) activeOrder = enricher_->enricher->options().descriptors.deformationOrder;
  }
  if (set) {
    const int built = deformationOrder(*set);
    if (requested.hermiteOrder > built)
      throw InvalidInputError("Hermite order " + std::to_string(requested.hermiteOrder) +
                              " refused: the active example set stores deformation moments up to order " +
                              std::to_string(built) + " only");
    const int order = requested.hermiteOrder > 0 ? requested.hermiteOrder : built;
    // New descriptors on both sides, or another blend: a new enricher, fitted again for them.
    if (activeOrder != 0 && (order != activeOrder || requested.blend != knobs().blend)) return installConfiguration(set, requested);
  }
  std::lock_guard<std::mutex> lock(mutex_);
  if (enricher_ && enricher_->enricher) {  // the values were checked above, so none of these throws
    ContactEnricher& enricher = *enricher_->enricher;
    // The set's stamp scale applies as when the enricher was built.
    enricher.setDetailGain(requested.gain.withStampGainTimes(enricher_->stampScale));
    enricher.setKernelWidths(requested.sigmaRho, requested.sigmaU);  // O(N^3) in the examples: cheap
  }
  if (requested.temporalSmoothing != temporalFilter_.timeConstant()) temporalFilter_.setTimeConstant(requested.temporalSmoothing);
  knobs_ = requested;
  ++configVersion_;  // the next state is computed afresh (and a rest surface being built gets these knobs)
  changed_.notify_all();
}

KnobOptions EnrichmentSession::knobs() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return knobs_;
}

bool EnrichmentSession::hasExampleSet() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return set_ != nullptr;
}

std::size_t EnrichmentSession::exampleCount() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return set_ ? set_->examples.size() : 0;
}

SessionDiagnostics EnrichmentSession::diagnostics() const {
  std::lock_guard<std::mutex> lock(mutex_);
  SessionDiagnostics d = stats_;
  d.restVertices = active_ ? active_->geometry.surface.numVertices() : 0;
  d.rebuilding = pending_ != nullptr;
  d.hasExamples = set_ != nullptr;
  if (enricher_ && enricher_->enricher) {
    const ContactEnricher& enricher = *enricher_->enricher;
    d.siteDensity = enricher_->siteDensity;
    d.hermiteOrder = enricher.options().descriptors.deformationOrder;
    d.widths = enricher.blender()->widths();
    d.fittedWidths = enricher.loadedWidths();
    d.blend = toString(enricher.blender()->method());
    d.materialSimilarity = enricher_->materialSimilarity;
    d.stampScale = enricher_->stampScale;
  }
  return d;
}

}  // namespace deformation_enrichment::enrichment
