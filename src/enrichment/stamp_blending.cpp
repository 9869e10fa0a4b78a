#include "deformation_enrichment/enrichment/stamp_blending.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <nanoflann.hpp>
#include <string>

#include "deformation_enrichment/enrichment/stamp.hpp"
#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::enrichment {

cv::Mat blendStamps(const std::vector<cv::Mat>& stamps, const Eigen::VectorXd& weights) {
  if (stamps.empty()) throw InvalidInputError("blendStamps: no stamps");
  if (static_cast<std::size_t>(weights.size()) != stamps.size())
    throw InvalidInputError("blendStamps: " + std::to_string(weights.size()) + " weights for " + std::to_string(stamps.size()) + " stamps");
  if (!weights.allFinite()) throw InvalidInputError("blendStamps: weights are not finite");
  for (std::size_t i = 0; i < stamps.size(); ++i) {
    if (stamps[i].type() != CV_32FC3) throw InvalidInputError("blendStamps: stamp " + std::to_string(i) + " is not CV_32FC3");
    if (stamps[i].size() != stamps[0].size()) throw InvalidInputError("blendStamps: stamp " + std::to_string(i) + " differs in size from stamp 0");
  }
  // eq. (16): Psi = sum_i Psi[i] w~_i, node by node.
  cv::Mat blended(stamps[0].size(), CV_32FC3, cv::Scalar::all(0.0));
  for (std::size_t i = 0; i < stamps.size(); ++i) {
    const double w = weights[static_cast<Eigen::Index>(i)];
    if (w == 0.0) continue;
    cv::scaleAdd(stamps[i], w, blended, blended);
  }
  return blended;
}

cv::Mat blendExampleStamps(const std::vector<examples::Example>& examples, const Eigen::VectorXd& weights, double& radius) {
  if (examples.empty()) throw InvalidInputError("blendExampleStamps: no examples");
  std::vector<cv::Mat> stamps;
  stamps.reserve(examples.size());
  for (std::size_t i = 0; i < examples.size(); ++i) {
    // Radii must agree to a relative 1e-9: one grid, one meaning of a node.
    if (std::abs(examples[i].stampRadius - examples[0].stampRadius) > 1e-9 * examples[0].stampRadius)
      throw InvalidInputError("blendExampleStamps: example " + std::to_string(i) + " has a different stamp radius");
    if (examples[i].stampLayers != examples[0].stampLayers)
      throw InvalidInputError("blendExampleStamps: example " + std::to_string(i) + " has a different number of stamp layers");
    stamps.push_back(examples[i].stamp);
  }
  radius = examples[0].stampRadius;
  return blendStamps(stamps, weights);
}

using Matches = std::vector<std::pair<Eigen::Index, double>>;

// nanoflann over the rest vertices (column-major 3 x n). The adaptor keeps a reference to its matrix, so the
// tree owns a copy on the heap: moving the StampMapper (and a ContactEnricher with it) leaves it valid.
struct StampMapper::KdTree {
  using Tree = nanoflann::KDTreeEigenMatrixAdaptor<Eigen::Matrix3Xd, 3, nanoflann::metric_L2_Simple, false>;
  explicit KdTree(const Eigen::Matrix3Xd& rest) : points(rest), tree(3, std::cref(points), 16) {}

  /// Rest vertices within the ball (distance below the radius), restricted to those reached through
  /// `surface` unless it is empty. A contact stays on the same rest point for many frames (the tool holds
  /// the tissue it touches), so the last few balls are kept and reused on an exact match.
  const Matches& ball(const Eigen::Vector3d& centre, double squaredRadius, const mesh::VertexAdjacency& surface) {
    for (const Ball& b : recent)
      if (b.valid && b.centre == centre && b.squaredRadius == squaredRadius) return b.matches;
    Ball& b = recent[next];
    next = (next + 1) % recent.size();
    b.matches.clear();
    if (surface.numVertices() != 0) walk(centre, squaredRadius, surface, b.matches);
    else tree.index->radiusSearch(centre.data(), squaredRadius, b.matches, nanoflann::SearchParams(32, 0.0f, false));
    b.centre = centre;
    b.squaredRadius = squaredRadius;
    b.valid = true;
    return b.matches;
  }

  /// The ball's vertices connected to the vertex nearest the centre over edges with both ends in the ball:
  /// a breadth-first walk from it, so work and touched memory are the ball's vertices and their one-rings,
  /// never O(n) (a radius search and a filter would visit the ball twice).
  void walk(const Eigen::Vector3d& centre, double squaredRadius, const mesh::VertexAdjacency& surface, Matches& matches) {
    Eigen::Index seed = 0;
    double seedDistance = 0.0;
    tree.index->knnSearch(centre.data(), 1, &seed, &seedDistance);
    if (!(seedDistance < squaredRadius)) return;
    if (++epoch == 0) {  // the marks wrapped around: clear them once every 2^32 walks
      std::fill(visited.begin(), visited.end(), 0u);
      epoch = 1;
    }
    visited[static_cast<std::size_t>(seed)] = epoch;
    matches.emplace_back(seed, seedDistance);
    for (std::size_t head = 0; head < matches.size(); ++head) {
      const int vertex = static_cast<int>(matches[head].first);
      for (const int* u = surface.begin(vertex); u != surface.end(vertex); ++u) {
        std::uint32_t& mark = visited[static_cast<std::size_t>(*u)];
        if (mark == epoch) continue;
        mark = epoch;  // inside or outside, each vertex is measured once
        const double distance = (points.col(*u) - centre).squaredNorm();
        if (distance < squaredRadius) matches.emplace_back(*u, distance);
      }
    }
  }

  struct Ball {
    bool valid = false;
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    double squaredRadius = 0.0;
    Matches matches;
  };
  Eigen::Matrix3Xd points;  // before `tree`, which refers to it
  Tree tree;
  std::array<Ball, 4> recent;  // a few tools at once
  std::size_t next = 0;
  std::vector<std::uint32_t> visited;  // walk marks: == epoch once measured in the current walk
  std::uint32_t epoch = 0;
};

StampMapper::StampMapper(Eigen::Matrix3Xd restVertices, double rimBand, Eigen::Matrix3Xd restNormals,
                         const Eigen::Matrix3Xi& restTriangles)
    : rest_(std::move(restVertices)), rimBand_(rimBand), normals_(std::move(restNormals)) {
  if (rest_.cols() == 0) throw InvalidInputError("StampMapper: the rest surface has no vertices");
  if (normals_.cols() != 0 && normals_.cols() != rest_.cols())
    throw InvalidInputError("StampMapper: " + std::to_string(normals_.cols()) + " normals for " + std::to_string(rest_.cols()) + " vertices");
  if (!normals_.allFinite()) throw InvalidInputError("StampMapper: rest normals are not finite");
  if (!rest_.allFinite()) throw InvalidInputError("StampMapper: rest vertices are not finite");
  if (!(rimBand >= 0.0 && rimBand < 1.0)) throw InvalidInputError("StampMapper: rim band must lie in [0, 1)");
  if (restTriangles.cols() != 0) adjacency_ = mesh::vertexAdjacency(restTriangles, rest_.cols());
  index_ = std::make_unique<KdTree>(rest_);
  if (adjacency_.numVertices() != 0) index_->visited.assign(static_cast<std::size_t>(rest_.cols()), 0u);
  slot_.assign(static_cast<std::size_t>(rest_.cols()), -1);
}

StampMapper::~StampMapper() = default;
StampMapper::StampMapper(StampMapper&&) noexcept = default;
StampMapper& StampMapper::operator=(StampMapper&&) noexcept = default;

void StampMapper::map(const std::vector<ContactStamp>& contacts, SurfaceEnrichment& out) {
  for (std::size_t c = 0; c < contacts.size(); ++c) {
    const ContactStamp& contact = contacts[c];
    const std::string what = "StampMapper::map: contact " + std::to_string(c);
    checkStamp(contact.stamp, contact.radius, contact.layers, what.c_str());
    if (!contact.contact.allFinite() || !contact.frame.allFinite() || !contact.rotation.allFinite())
      throw InvalidInputError(what + ": contact, frame or rotation is not finite");
    if ((contact.frame.transpose() * contact.frame - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-6)
      throw InvalidInputError(what + ": frame B is not orthonormal");
    if ((contact.rotation.transpose() * contact.rotation - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-6)
      throw InvalidInputError(what + ": rotation R is not orthonormal");
  }
  touched_.clear();
  sums_.clear();
  weights_.clear();
  for (const ContactStamp& contact : contacts) {
    const Eigen::Matrix3d RB = contact.rotation * contact.frame;
    const double inverseRadius = 1.0 / contact.radius;
    const Eigen::Matrix3Xd& rest = index_->points;  // = rest_, and in the cache after the ball's walk
    for (const auto& [vertex, squaredDistance] : index_->ball(contact.contact, contact.radius * contact.radius, adjacency_)) {
      const double a = rimWeight(std::sqrt(squaredDistance) * inverseRadius);
      if (a == 0.0) continue;
      const bool volume = contact.layers > 1;
      if (!volume && normals_.cols() != 0 && normals_.col(vertex).dot(contact.frame.col(2)) < 0.0) continue;  // far side
      const Eigen::Vector3d x = rest.col(vertex) - contact.contact;
      const double phi = contact.frame.col(0).dot(x), varphi = contact.frame.col(1).dot(x);
      // e_c(x) = R B Psi(phi, varphi[, zeta]) (eq. 1), weighted by the rim weight a_c(x).
      const Eigen::Vector3d psi = volume ? sampleVolumeStamp(contact.stamp, contact.radius, contact.layers, phi, varphi, contact.frame.col(2).dot(x))
                                         : sampleStamp(contact.stamp, contact.radius, phi, varphi);
      const Eigen::Vector3d e = a * (RB * psi);
      int& slot = slot_[static_cast<std::size_t>(vertex)];
      if (slot < 0) {  // first stamp on this vertex: a new compact entry
        slot = static_cast<int>(touched_.size());
        touched_.push_back(static_cast<int>(vertex));
        sums_.push_back(e);
        weights_.push_back(a);
      } else {
        sums_[static_cast<std::size_t>(slot)] += e;
        weights_[static_cast<std::size_t>(slot)] += a;
      }
    }
  }
  // Ascending ids: a scan of the touched id range (slot_ marks touched vertices) is linear and beats
  // sorting once the stamp covers thousands of vertices (bench_contact_enricher).
  if (!touched_.empty()) {
    const auto [low, high] = std::minmax_element(touched_.begin(), touched_.end());
    const std::size_t range = static_cast<std::size_t>(*high - *low) + 1;
    if (range < 8 * touched_.size()) {
      const int first = *low;
      std::size_t k = 0;
      for (std::size_t v = 0; v < range; ++v)
        if (slot_[static_cast<std::size_t>(first) + v] >= 0) touched_[k++] = first + static_cast<int>(v);
    } else {
      std::sort(touched_.begin(), touched_.end());
    }
  }
  out.vertices = touched_;
  out.displacements.resize(3, static_cast<Eigen::Index>(touched_.size()));
  for (std::size_t k = 0; k < touched_.size(); ++k) {
    int& slot = slot_[static_cast<std::size_t>(touched_[k])];
    const auto entry = static_cast<std::size_t>(slot);
    const double weight = weights_[entry];  // at most 1 unless stamps overlap
    out.displacements.col(static_cast<Eigen::Index>(k)) = weight > 1.0 ? Eigen::Vector3d(sums_[entry] / weight) : sums_[entry];
    slot = -1;  // reset for the next call, touching only what was used
  }
}

void StampMapper::apply(const SurfaceEnrichment& enrichment, Eigen::Matrix3Xd& state) const {
  if (state.cols() != rest_.cols())
    throw InvalidInputError("StampMapper::apply: state has " + std::to_string(state.cols()) + " vertices, the surface " +
                            std::to_string(rest_.cols()));
  if (static_cast<Eigen::Index>(enrichment.vertices.size()) != enrichment.displacements.cols())
    throw InvalidInputError("StampMapper::apply: vertex ids and displacements differ in count");
  for (std::size_t k = 0; k < enrichment.vertices.size(); ++k) {
    const int v = enrichment.vertices[k];
    if (v < 0 || v >= rest_.cols()) throw InvalidInputError("StampMapper::apply: vertex id " + std::to_string(v) + " out of range");
    state.col(v) += enrichment.displacements.col(static_cast<Eigen::Index>(k));  // eq. (1): s~ = s + e
  }
}

}  // namespace deformation_enrichment::enrichment
