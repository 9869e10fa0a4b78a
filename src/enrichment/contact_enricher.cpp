#include "deformation_enrichment/enrichment/contact_enricher.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <string>
#include <type_traits>

#include "deformation_enrichment/all_finite.hpp"
#include "deformation_enrichment/descriptors/deformation_descriptor.hpp"
#include "deformation_enrichment/descriptors/interior_sampling.hpp"
#include "deformation_enrichment/descriptors/moment_window.hpp"
#include "deformation_enrichment/descriptors/site_density.hpp"
#include "deformation_enrichment/descriptors/stamping_frame.hpp"
#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/closest_point_on_triangle.hpp"
#include "deformation_enrichment/smooth_ramp.hpp"

namespace deformation_enrichment::enrichment {
namespace {

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// One third of every incident triangle's area: the surface quadrature weight of a vertex.
Eigen::VectorXd vertexAreas(const mesh::TriangleMesh& surface) {
  Eigen::VectorXd areas = Eigen::VectorXd::Zero(surface.vertices.cols());
  for (Eigen::Index f = 0; f < surface.triangles.cols(); ++f) {
    const Eigen::Vector3d a = surface.vertices.col(surface.triangles(0, f));
    const Eigen::Vector3d b = surface.vertices.col(surface.triangles(1, f));
    const Eigen::Vector3d c = surface.vertices.col(surface.triangles(2, f));
    const double third = (b - a).cross(c - a).norm() / 6.0;
    for (int k = 0; k < 3; ++k) areas(surface.triangles(k, f)) += third;
  }
  return areas;
}

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

}  // namespace

ContactEnricher::ContactEnricher(mesh::TriangleMesh restSurface, const ContactEnricherOptions& options,
                                 std::optional<descriptors::PointSampling> siteDensity)
    : options_(options),
      rest_(std::move(restSurface)),
      mapper_((checkOptions(options), mesh::validate(rest_, false), rest_.vertices), options.rimBand, mesh::vertexNormals(rest_),
              rest_.triangles) {
  restNormals_ = mesh::vertexNormals(rest_);
  vertexTriangles_.assign(static_cast<std::size_t>(rest_.vertices.cols()), {});
  for (Eigen::Index f = 0; f < rest_.triangles.cols(); ++f)
    for (int k = 0; k < 3; ++k) vertexTriangles_[static_cast<std::size_t>(rest_.triangles(k, f))].push_back(static_cast<int>(f));
  // rho integrates the material's indicator (eq. 7): volume samples of the material around the surface.
  if (!siteDensity)
    siteDensity = descriptors::sampleClosedSurfaceInterior(
        rest_, descriptors::forWindow({}, options_.descriptors.window.scale, options_.sampleSpacing).spacing);
  siteEvaluator_ = std::make_unique<descriptors::DescriptorEvaluator>(std::move(*siteDensity), rest_, std::vector<int>(),
                                                                      options_.descriptors);
  // mu is fitted on what the run time has: the surface vertices, weighted by their areas.
  surfaceSampling_ = std::make_unique<descriptors::PointSampling>(rest_.vertices, vertexAreas(rest_));
  siteCache_.assign(static_cast<std::size_t>(rest_.vertices.cols()), std::nullopt);
}

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
  if (current.cols() != rest_.vertices.cols())
    throw InvalidInputError("contact enricher: " + std::to_string(current.cols()) + " current positions for " +
                            std::to_string(rest_.vertices.cols()) + " surface vertices");
  if (check == StateCheck::Full && !allFiniteValues(current)) throw InvalidInputError("contact enricher: non-finite current surface positions");
}

const descriptors::Window& ContactEnricher::surfaceWindow(const Eigen::Vector3d& p) const {
  // The window's samples, offsets and weights depend on rest positions only, and a contact stays on the
  // same rest point while the tool holds the tissue: reuse the last few windows on an exact match.
  for (const auto& w : recentWindows_)
    if (w && w->centre == p) return *w;
  auto& slot = recentWindows_[nextWindow_];
  nextWindow_ = (nextWindow_ + 1) % recentWindows_.size();
  slot = descriptors::gatherWindow(*surfaceSampling_, p, options_.descriptors.window);
  return *slot;
}

template <typename Positions>
Eigen::Vector3d ContactEnricher::currentNormal(const Positions& current, int vertex) const {
  Eigen::Vector3d n = Eigen::Vector3d::Zero();
  for (int f : vertexTriangles_[static_cast<std::size_t>(vertex)]) {
    const Eigen::Vector3d a = current.col(rest_.triangles(0, f)).template cast<double>();
    const Eigen::Vector3d b = current.col(rest_.triangles(1, f)).template cast<double>();
    const Eigen::Vector3d c = current.col(rest_.triangles(2, f)).template cast<double>();
    n += (b - a).cross(c - a);  // area-weighted
  }
  const double length = n.norm();
  return length > 0.0 ? Eigen::Vector3d(n / length) : Eigen::Vector3d(restNormals_.col(vertex));
}

template <typename Positions>
int ContactEnricher::nearestVertex(const Positions& current, const Eigen::Vector3d& point) const {
  // Squared distances into a contiguous buffer (a loop the compiler vectorises), then the smallest one's
  // first index: two short passes instead of one scalar scan over every vertex.
  using Scalar = typename Positions::Scalar;
  auto& distances = [this]() -> auto& {
    if constexpr (std::is_same_v<Scalar, float>) return floatDistances_;
    else return doubleDistances_;
  }();
  distances.resize(current.cols());
  const Scalar* xyz = current.data();
  const Scalar px = static_cast<Scalar>(point.x()), py = static_cast<Scalar>(point.y()), pz = static_cast<Scalar>(point.z());
  for (Eigen::Index v = 0; v < current.cols(); ++v) {
    const Scalar dx = xyz[3 * v] - px, dy = xyz[3 * v + 1] - py, dz = xyz[3 * v + 2] - pz;
    distances[v] = dx * dx + dy * dy + dz * dz;
  }
  const Scalar smallest = distances.minCoeff();
  Eigen::Index v = 0;
  while (distances[v] != smallest) ++v;
  return static_cast<int>(v);
}

template <typename Positions>
void ContactEnricher::locate(const Positions& positions, int vertex, const Eigen::Vector3d& point, ContactDescription& d) const {
  // The nearest surface point lies on a triangle around the nearest vertex, or on one next to those: search
  // the triangles of the vertex's one-ring (a few dozen), not the mesh.
  double best = std::numeric_limits<double>::infinity();
  d.corners = Eigen::Vector3i::Constant(vertex);  // a vertex no triangle uses stays alone
  d.barycentric = Eigen::Vector3d::UnitX();
  for (int f : vertexTriangles_[static_cast<std::size_t>(vertex)])
    for (int k = 0; k < 3; ++k)
      for (int g : vertexTriangles_[static_cast<std::size_t>(rest_.triangles(k, f))]) {
        const Eigen::Vector3i t = rest_.triangles.col(g);
        const Eigen::Vector3d a = positions.col(t(0)).template cast<double>(), b = positions.col(t(1)).template cast<double>(),
                              c = positions.col(t(2)).template cast<double>();
        const Eigen::Vector3d closest = mesh::closestPointOnTriangle(point, a, b, c);
        const double distance = (closest - point).squaredNorm();
        if (distance < best) {
          best = distance;
          d.corners = t;
          d.barycentric = mesh::barycentricOnTriangle(closest, a, b, c);
        }
      }
  Eigen::Index corner = 0;
  d.barycentric.maxCoeff(&corner);
  d.vertex = d.corners(corner);
}

const hermite::MomentList& ContactEnricher::siteMoments(int vertex) const {
  auto& site = siteCache_[static_cast<std::size_t>(vertex)];
  if (!site) {  // rho depends on the rest shape only: once per rest vertex
    const auto& opt = options_.descriptors;
    const descriptors::Window window = descriptors::gatherWindow(siteEvaluator_->sampling(), rest_.vertices.col(vertex), opt.window);
    site = descriptors::densityMoments(window, 0, opt.siteOrder);
  }
  return *site;
}

ContactDescription ContactEnricher::describe(const Eigen::Matrix3Xd& current, const Contact& contact) const {
  checkState(current);
  return describeValidState(current, contact);
}

template <typename Positions>
ContactDescription ContactEnricher::describeValidState(const Positions& current, const Contact& contact) const {
  if (!contact.point.allFinite()) throw InvalidInputError("contact enricher: non-finite contact point");
  if (contact.normal && !contact.normal->allFinite()) throw InvalidInputError("contact enricher: non-finite contact normal");
  ContactDescription d;
  if (contact.restState) {
    locate(rest_.vertices, siteEvaluator_->nearestSurfaceVertex(contact.point), contact.point, d);
    d.p = contact.point;
  } else {
    locate(current, nearestVertex(current, contact.point), contact.point, d);
    d.p = rest_.vertices(Eigen::all, d.corners) * d.barycentric;
  }
  // Everything that depends on where the contact is follows it continuously: rho and both normals are
  // interpolated over its triangle.
  hermite::MomentList site = siteMoments(d.corners(0));
  site.values() *= d.barycentric(0);
  Eigen::Vector3d restNormal = Eigen::Vector3d::Zero(), deformedNormal = Eigen::Vector3d::Zero();
  for (int k = 0; k < 3; ++k) {
    if (k > 0) site.values() += d.barycentric(k) * siteMoments(d.corners(k)).values();
    restNormal += d.barycentric(k) * restNormals_.col(d.corners(k));
    deformedNormal += d.barycentric(k) * currentNormal(current, d.corners(k));
  }
  if (!(restNormal.norm() > 1e-12)) restNormal = restNormals_.col(d.vertex);  // opposite normals across a sharp edge
  if (!(deformedNormal.norm() > 1e-12)) deformedNormal = currentNormal(current, d.vertex);
  restNormal.normalize();
  deformedNormal.normalize();
  const auto& opt = options_.descriptors;
  const descriptors::Window& window = surfaceWindow(d.p);
  if (window.empty()) throw InvalidInputError("contact enricher: no surface vertex within the window of the contact");
  // eq. (10)-(11) in kinematics' surface mode: the normals complete F where the samples are coplanar.
  const descriptors::DeformationDescriptor deformation = descriptors::windowDeformationDescriptor(
      window, rest_.vertices(Eigen::all, window.indices), current(Eigen::all, window.indices).template cast<double>(),
      opt.deformationOrder, &restNormal, &deformedNormal, opt.mls);
  const Eigen::Vector3d normal = contact.normal ? *contact.normal : restNormal;
  const descriptors::StampingFrame frame = descriptors::stampingFrame(
      normal, site, &deformation.mu, opt.frameTolerance, contact.previousFrameAxis ? &*contact.previousFrameAxis : nullptr);
  d.B = frame.B;
  d.R = deformation.R;
  d.frameRule = frame.rule;
  d.rho = site.transformed(d.B.transpose());  // world -> frame B (Appendix B)
  d.mu = deformation.mu.transformed(d.B.transpose());
  return d;
}

void ContactEnricher::blendContact(const Contact& contact, ContactOutcome& outcome, ContactStamp& stamp) {
  blender_->blend(outcome.description.rho, outcome.description.mu, blendScratch_);  // eq. 15 -> RBF -> eq. 16
  outcome.weights = blendScratch_.rbf.weights;
  outcome.confidence = blendScratch_.rbf.confidence;
  outcome.muNorm = outcome.description.mu.values().norm();
  Eigen::VectorXd effective;
  const bool followsMagnitude = options_.magnitudeAware || blender_->method() == BlendMethod::Regression;
  if (blender_->method() == BlendMethod::Regression) {
    // The regression is linear in mu: beyond maxMagnitudeRatio times the largest example it stops growing.
    const double reach = options_.maxMagnitudeRatio * blender_->largestMuNorm();
    effective = outcome.weights * (outcome.muNorm > reach ? reach / outcome.muNorm : 1.0);
  } else {
    // Psi = sum_i w~_i (|mu| / |mu[i]|) Psi[i] when magnitude-aware (examples without deformation, |mu[i]| = 0,
    // contribute nothing), with w~_i and the ratio clamped (options).
    effective = outcome.weights.cwiseMax(-options_.maxWeight).cwiseMin(options_.maxWeight);
    if (options_.magnitudeAware)
      for (Eigen::Index i = 0; i < effective.size(); ++i)
        effective(i) = muNorms_(i) > 0.0 ? effective(i) * std::min(outcome.muNorm / muNorms_(i), options_.maxMagnitudeRatio) : 0.0;
  }
  outcome.detailScale = smoothRamp(outcome.confidence, options_.gain.minConfidence);
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
    outcome.description = describeValidState(current, contacts[c]);  // the state was checked once above
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
