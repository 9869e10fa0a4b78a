#include "deformation_enrichment/enrichment/contact_describer.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <type_traits>

#include "deformation_enrichment/descriptors/deformation_descriptor.hpp"
#include "deformation_enrichment/descriptors/interior_sampling.hpp"
#include "deformation_enrichment/descriptors/moment_window.hpp"
#include "deformation_enrichment/descriptors/site_density.hpp"
#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/closest_point_on_triangle.hpp"

namespace deformation_enrichment::enrichment {
namespace {

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

}  // namespace

ContactDescriber::ContactDescriber(mesh::TriangleMesh restSurface, const descriptors::DescriptorOptions& options,
                                   double sampleSpacing, std::optional<descriptors::PointSampling> siteDensity)
    : options_(options), rest_(std::move(restSurface)) {
  mesh::validate(rest_, false);
  restNormals_ = mesh::vertexNormals(rest_);
  vertexTriangles_.assign(static_cast<std::size_t>(rest_.vertices.cols()), {});
  for (Eigen::Index f = 0; f < rest_.triangles.cols(); ++f)
    for (int k = 0; k < 3; ++k) vertexTriangles_[static_cast<std::size_t>(rest_.triangles(k, f))].push_back(static_cast<int>(f));
  // rho integrates the material's indicator (eq. 7): volume samples of the material around the surface.
  if (!siteDensity)
    siteDensity = descriptors::sampleClosedSurfaceInterior(rest_, descriptors::forWindow({}, options_.window.scale, sampleSpacing).spacing);
  siteEvaluator_ = std::make_unique<descriptors::DescriptorEvaluator>(std::move(*siteDensity), rest_, std::vector<int>(), options_);
  // mu is fitted on what the run time has: the surface vertices, weighted by their areas.
  surfaceSampling_ = std::make_unique<descriptors::PointSampling>(rest_.vertices, vertexAreas(rest_));
  siteCache_.assign(static_cast<std::size_t>(rest_.vertices.cols()), std::nullopt);
}

const descriptors::Window& ContactDescriber::surfaceWindow(const Eigen::Vector3d& p) const {
  // The window's samples, offsets and weights depend on rest positions only, and a contact stays on the
  // same rest point while the tool holds the tissue: reuse the last few windows on an exact match.
  for (const auto& w : recentWindows_)
    if (w && w->centre == p) return *w;
  auto& slot = recentWindows_[nextWindow_];
  nextWindow_ = (nextWindow_ + 1) % recentWindows_.size();
  slot = descriptors::gatherWindow(*surfaceSampling_, p, options_.window);
  return *slot;
}

template <typename Positions>
Eigen::Vector3d ContactDescriber::currentNormal(const Positions& current, int vertex) const {
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
int ContactDescriber::nearestVertex(const Positions& current, const Eigen::Vector3d& point) const {
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
void ContactDescriber::locate(const Positions& positions, int vertex, const Eigen::Vector3d& point, ContactDescription& d) const {
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

const hermite::MomentList& ContactDescriber::siteMoments(int vertex) const {
  auto& site = siteCache_[static_cast<std::size_t>(vertex)];
  if (!site) {  // rho depends on the rest shape only: once per rest vertex
    const auto& opt = options_;
    const descriptors::Window window = descriptors::gatherWindow(siteEvaluator_->sampling(), rest_.vertices.col(vertex), opt.window);
    site = descriptors::densityMoments(window, 0, opt.siteOrder);
  }
  return *site;
}

template <typename Positions>
ContactDescription ContactDescriber::describe(const Positions& current, const Contact& contact) const {
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
  const auto& opt = options_;
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

template ContactDescription ContactDescriber::describe(const Eigen::Matrix3Xd&, const Contact&) const;
template ContactDescription ContactDescriber::describe(const Eigen::Matrix3Xf&, const Contact&) const;

}  // namespace deformation_enrichment::enrichment
