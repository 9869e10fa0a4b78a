#include "deformation_enrichment/enrichment/stamp_blending.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
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
    stamps.push_back(examples[i].stamp);
  }
  radius = examples[0].stampRadius;
  return blendStamps(stamps, weights);
}

namespace {

using Matches = std::vector<std::pair<Eigen::Index, double>>;

// Keeps, in their order, the matches reached from the one nearest the centre (ties: the lower vertex id)
// over edges with both ends in the ball. `slot` has one entry per vertex, -1 on entry and on exit; while
// walking it holds k for the unreached match k and -2 - k once reached. Work and touched memory are the
// ball's vertices and their one-rings, never O(n).
void keepReachedThroughSurface(Matches& matches, const mesh::VertexAdjacency& surface, std::vector<int>& slot,
                               std::vector<int>& queue) {
  if (matches.empty()) return;
  std::size_t seed = 0;
  for (std::size_t k = 1; k < matches.size(); ++k)
    if (matches[k].second < matches[seed].second || (matches[k].second == matches[seed].second && matches[k].first < matches[seed].first))
      seed = k;
  for (std::size_t k = 0; k < matches.size(); ++k) slot[static_cast<std::size_t>(matches[k].first)] = static_cast<int>(k);
  queue.assign(1, static_cast<int>(matches[seed].first));
  slot[static_cast<std::size_t>(queue[0])] = -2 - static_cast<int>(seed);
  for (std::size_t head = 0; head < queue.size(); ++head)
    for (const int* u = surface.begin(queue[head]); u != surface.end(queue[head]); ++u)
      if (int& s = slot[static_cast<std::size_t>(*u)]; s >= 0) {
        s = -2 - s;
        queue.push_back(*u);
      }
  std::size_t kept = 0;
  for (std::size_t k = 0; k < matches.size(); ++k) {
    int& s = slot[static_cast<std::size_t>(matches[k].first)];
    if (s <= -2) matches[kept++] = matches[k];
    s = -1;
  }
  matches.resize(kept);
}

}  // namespace

// nanoflann over the rest vertices (column-major 3 x n). The adaptor keeps a reference to its matrix, so the
// tree owns a copy on the heap: moving the StampMapper (and a ContactEnricher with it) leaves it valid.
struct StampMapper::KdTree {
  using Tree = nanoflann::KDTreeEigenMatrixAdaptor<Eigen::Matrix3Xd, 3, nanoflann::metric_L2_Simple, false>;
  explicit KdTree(const Eigen::Matrix3Xd& rest) : points(rest), tree(3, std::cref(points), 16) {}

  /// Rest vertices within the ball, restricted to those reached through `surface` unless it is empty. A
  /// contact stays on the same rest point for many frames (the tool holds the tissue it touches), so the
  /// last few (filtered) balls are kept and reused on an exact match.
  const Matches& ball(const Eigen::Vector3d& centre, double squaredRadius, const mesh::VertexAdjacency& surface) {
    for (const Ball& b : recent)
      if (b.valid && b.centre == centre && b.squaredRadius == squaredRadius) return b.matches;
    Ball& b = recent[next];
    next = (next + 1) % recent.size();
    b.matches.clear();
    tree.index->radiusSearch(centre.data(), squaredRadius, b.matches, nanoflann::SearchParams(32, 0.0f, false));
    if (surface.numVertices() != 0) keepReachedThroughSurface(b.matches, surface, slot, queue);
    b.centre = centre;
    b.squaredRadius = squaredRadius;
    b.valid = true;
    return b.matches;
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
  std::vector<int> slot, queue;  // scratch of keepReachedThroughSurface (slot: one per vertex, given triangles)
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
  if (adjacency_.numVertices() != 0) index_->slot.assign(static_cast<std::size_t>(rest_.cols()), -1);
  sum_ = Eigen::Matrix3Xd::Zero(3, rest_.cols());
  weightSum_ = Eigen::VectorXd::Zero(rest_.cols());
}

StampMapper::~StampMapper() = default;
StampMapper::StampMapper(StampMapper&&) noexcept = default;
StampMapper& StampMapper::operator=(StampMapper&&) noexcept = default;

double StampMapper::rimWeight(double r) const {
  if (r > 1.0) return 0.0;
  if (rimBand_ == 0.0) return 1.0;
  const double s = std::clamp((1.0 - r) / rimBand_, 0.0, 1.0);
  return s * s * (3.0 - 2.0 * s);  // smoothstep: C1 at both ends of the band
}

void StampMapper::map(const std::vector<ContactStamp>& contacts, SurfaceEnrichment& out) {
  for (std::size_t c = 0; c < contacts.size(); ++c) {
    const ContactStamp& contact = contacts[c];
    const std::string what = "StampMapper::map: contact " + std::to_string(c);
    checkStamp(contact.stamp, contact.radius, what.c_str());
    if (!contact.contact.allFinite() || !contact.frame.allFinite() || !contact.rotation.allFinite())
      throw InvalidInputError(what + ": contact, frame or rotation is not finite");
    if ((contact.frame.transpose() * contact.frame - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-6)
      throw InvalidInputError(what + ": frame B is not orthonormal");
    if ((contact.rotation.transpose() * contact.rotation - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-6)
      throw InvalidInputError(what + ": rotation R is not orthonormal");
  }
  touched_.clear();
  for (const ContactStamp& contact : contacts) {
    const Eigen::Matrix3d RB = contact.rotation * contact.frame;
    for (const auto& [vertex, squaredDistance] : index_->ball(contact.contact, contact.radius * contact.radius, adjacency_)) {
      const double a = rimWeight(std::sqrt(squaredDistance) / contact.radius);
      if (a == 0.0) continue;
      if (normals_.cols() != 0 && normals_.col(vertex).dot(contact.frame.col(2)) < 0.0) continue;  // far side
      const Eigen::Vector3d x = rest_.col(vertex) - contact.contact;
      const double phi = contact.frame.col(0).dot(x), varphi = contact.frame.col(1).dot(x);
      if (weightSum_[vertex] == 0.0) touched_.push_back(static_cast<int>(vertex));
      // e_c(x) = R B Psi(phi, varphi) (eq. 1), weighted by the rim weight a_c(x).
      sum_.col(vertex) += a * (RB * sampleStamp(contact.stamp, contact.radius, phi, varphi));
      weightSum_[vertex] += a;
    }
  }
  // Ascending ids: a scan of the touched id range (weightSum_ marks touched vertices) is linear and beats
  // sorting once the stamp covers thousands of vertices (bench_contact_enricher).
  if (!touched_.empty()) {
    const auto [low, high] = std::minmax_element(touched_.begin(), touched_.end());
    const std::size_t range = static_cast<std::size_t>(*high - *low) + 1;
    if (range < 8 * touched_.size()) {
      const int first = *low;
      std::size_t k = 0;
      for (std::size_t v = 0; v < range; ++v)
        if (weightSum_[first + static_cast<Eigen::Index>(v)] != 0.0) touched_[k++] = first + static_cast<int>(v);
    } else {
      std::sort(touched_.begin(), touched_.end());
    }
  }
  out.vertices = touched_;
  out.displacements.resize(3, static_cast<Eigen::Index>(touched_.size()));
  for (std::size_t k = 0; k < touched_.size(); ++k) {
    const int v = touched_[k];
    out.displacements.col(static_cast<Eigen::Index>(k)) = sum_.col(v) / std::max(1.0, weightSum_[v]);
    sum_.col(v).setZero();  // reset scratch for the next call, touching only what was used
    weightSum_[v] = 0.0;
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
