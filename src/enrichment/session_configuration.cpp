// The configuration side of EnrichmentSession: rest surfaces (built on the session's worker thread, so a cut
// never stalls the frame path), example sets and knobs (built on the caller's thread outside the frame lock),
// each installed between two states.
#include <chrono>
#include <cmath>

#include "deformation_enrichment/enrichment/descriptor_order.hpp"
#include "deformation_enrichment/enrichment/enrichment_session.hpp"
#include "deformation_enrichment/enrichment/example_set_options.hpp"
#include "deformation_enrichment/enrichment/material_similarity.hpp"
#include "deformation_enrichment/enrichment/surface_enricher.hpp"
#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/surface_report.hpp"
#include "session_built.hpp"

namespace deformation_enrichment::enrichment {
namespace {

bool sameGeometry(const RestGeometry& a, const RestGeometry& b) {
  const auto sameSurface = [](const mesh::TriangleMesh& x, const mesh::TriangleMesh& y) {
    return x.vertices.cols() == y.vertices.cols() && x.triangles.cols() == y.triangles.cols() && x.vertices == y.vertices &&
           x.triangles == y.triangles;
  };
  if (!sameSurface(a.surface, b.surface) || a.volume.has_value() != b.volume.has_value()) return false;
  return !a.volume || (a.volume->vertices.cols() == b.volume->vertices.cols() && a.volume->tets.cols() == b.volume->tets.cols() &&
                       a.volume->vertices == b.volume->vertices && a.volume->tets == b.volume->tets);
}

// What real display surfaces bring along and how it is handled (nothing here stops the enrichment).
bool flawed(const mesh::SurfaceReport& r) {
  return r.nonManifoldEdges > 0 || r.misorientedEdges > 0 || r.duplicateVertices > 0 || r.degenerateTriangles > 0;
}

std::string flawNote(const mesh::SurfaceReport& r) {
  std::string note;
  if (r.duplicateVertices > 0) note += "; duplicate vertices are kept apart (a stamp does not cross between them, as across a cut)";
  if (r.degenerateTriangles > 0) note += "; zero-area triangles add nothing to normals and areas";
  if (r.misorientedEdges > 0) note += "; inconsistent orientation: normals and a shell may point the wrong way there";
  return note;
}

void checkKnobs(const KnobOptions& k) {
  k.gain.check();
  if (!std::isfinite(k.sigmaRho) || !std::isfinite(k.sigmaU)) throw InvalidInputError("kernel widths must be finite");
  if (k.hermiteOrder < 0) throw InvalidInputError("Hermite order must be >= 0 (0: the set's)");
  if (!(k.temporalSmoothing >= 0.0) || !std::isfinite(k.temporalSmoothing))
    throw InvalidInputError("temporal smoothing must be >= 0 and finite");
}

}  // namespace

EnrichmentSession::EnrichmentSession(SessionOptions options)
    : options_(std::move(options)), continuity_(options_.continuity) {
  const descriptors::SiteDensityOptions& d = options_.density;
  if (!(d.maxOutside >= 0.0) || !std::isfinite(d.shellThickness))
    throw InvalidInputError("site density: max_outside must be >= 0 and the shell thickness finite");
  worker_ = std::thread([this] { rebuildLoop(); });
}

EnrichmentSession::~EnrichmentSession() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  changed_.notify_all();
  worker_.join();
}

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
  if (options_.scene && set.metadata.provenance)
    result->materialSimilarity = materialSimilarity(set.metadata.provenance->scene, *options_.scene);
  options.gain = {knobs.gain.stampGain * result->materialSimilarity, knobs.gain.minConfidence};
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

void EnrichmentSession::setRestGeometry(RestGeometry rest) {
  mesh::validate(rest.surface, false);
  if (rest.volume) mesh::validate(*rest.volume);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    const std::shared_ptr<const RestSurface>& newest = pending_ ? pending_ : active_;
    if (newest && sameGeometry(newest->geometry, rest)) return;
  }
  auto surface = std::make_shared<RestSurface>();
  surface->normals = mesh::vertexNormals(rest.surface);
  surface->geometry = std::move(rest);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    surface->version = nextRestVersion_++;
    if (pending_) ++stats_.supersededRebuilds;
    pending_ = std::move(surface);
  }
  changed_.notify_all();
}

void EnrichmentSession::rebuildLoop() {
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    changed_.wait(lock, [&] { return stopping_ || (pending_ && !building_); });
    if (stopping_) return;
    const std::shared_ptr<const RestSurface> rest = pending_;
    const std::shared_ptr<const examples::ExampleSet> set = set_;
    const KnobOptions knobs = knobs_;
    const std::uint64_t config = configVersion_;
    building_ = true;
    lock.unlock();
    const auto start = std::chrono::steady_clock::now();
    std::unique_ptr<Built> built;
    std::string error;
    mesh::SurfaceReport report;
    try {
      report = mesh::inspectSurface(rest->geometry.surface);
      built = set ? build(*rest, *set, knobs) : std::make_unique<Built>();
      built->restVersion = rest->version;
    } catch (const Error& e) {
      error = e.what();
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    lock.lock();
    // A newer rest surface, set or knob value arrived meanwhile: build again for it.
    const bool current = pending_ == rest && configVersion_ == config;
    std::unique_ptr<Built> old;
    std::string siteDensity;
    if (current) {
      pending_.reset();
      stats_.lastRebuildSeconds = seconds;
      if (!error.empty()) {
        stats_.lastRestError = rest->geometry.source + ": " + error;
      } else {
        built->configVersion = config;
        siteDensity = built->enricher ? built->siteDensity : "";
        old = std::move(enricher_);
        enricher_ = std::move(built);
        active_ = rest;
        ++stats_.rebuilds;
        resetStream();
      }
    }
    lock.unlock();
    old.reset();  // a large enricher is freed outside the lock
    if (current && !error.empty())
      log(SessionLogLevel::Error, "rest surface from " + rest->geometry.source + " refused: " + error +
                                      " (keeping the previous rest surface)");
    else if (current)
      log(flawed(report) ? SessionLogLevel::Warning : SessionLogLevel::Info,
          "rest surface from " + rest->geometry.source + ": " + mesh::describe(report) + flawNote(report) +
              "; enricher built in " + std::to_string(seconds) + " s" + (siteDensity.empty() ? "" : "; site density: " + siteDensity));
    lock.lock();
    building_ = false;  // only now, so waitForRebuild() returns after the outcome is logged
    changed_.notify_all();
  }
}

void EnrichmentSession::resetStream() {
  // A new topology invalidates states of the old one, and the tools' memory of it.
  continuity_.reset();
  temporalFilter_.reset();
  memo_.invalidate();
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
    // The set's material similarity scales the gain as when the enricher was built.
    enricher.setDetailGain({requested.gain.stampGain * enricher_->materialSimilarity, requested.gain.minConfidence});
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

std::shared_ptr<const RestSurface> EnrichmentSession::newestRest() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return pending_ ? pending_ : active_;
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
  }
  return d;
}

void EnrichmentSession::waitForRebuild() const {
  std::unique_lock<std::mutex> lock(mutex_);
  changed_.wait(lock, [&] { return !pending_ && !building_; });
}

}  // namespace deformation_enrichment::enrichment
