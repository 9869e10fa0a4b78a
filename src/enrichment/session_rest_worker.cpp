// The rest-surface side of EnrichmentSession: its worker thread, which builds the enricher of every new rest
// surface (a cut, a new organ) while the frame path goes on with the old one, and installs it between two states.
#include <chrono>

#include "deformation_enrichment/enrichment/enrichment_session.hpp"
#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/surface_report.hpp"
#include "deformation_enrichment/seconds_since.hpp"
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

}  // namespace

EnrichmentSession::EnrichmentSession(SessionOptions options)
    : options_(std::move(options)), continuity_(options_.continuity) {
  const descriptors::SiteDensityOptions& d = options_.density;
  if (!(d.maxOutside >= 0.0) || !std::isfinite(d.shellThickness))
    throw InvalidInputError("site density: max_outside must be >= 0 and the shell thickness finite");
  if (!(options_.transferGain >= 0.0) || !std::isfinite(options_.transferGain))
    throw InvalidInputError("transfer gain must be >= 0 and finite (0: the material similarity)");
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
    const double seconds = secondsSince(start);
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

std::shared_ptr<const RestSurface> EnrichmentSession::newestRest() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return pending_ ? pending_ : active_;
}

void EnrichmentSession::waitForRebuild() const {
  std::unique_lock<std::mutex> lock(mutex_);
  changed_.wait(lock, [&] { return !pending_ && !building_; });
}

}  // namespace deformation_enrichment::enrichment
