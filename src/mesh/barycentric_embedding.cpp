#include "deformation_enrichment/mesh/barycentric_embedding.hpp"

#include <Eigen/Dense>
#include <nanoflann.hpp>
#include <iomanip>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/closest_point_on_triangle.hpp"

namespace deformation_enrichment::mesh {
namespace {

/// nanoflann adaptor over the tet centroids (3 x T column-major).
struct CentroidCloud {
  const Eigen::Matrix3Xd& centroids;
  std::size_t kdtree_get_point_count() const { return static_cast<std::size_t>(centroids.cols()); }
  double kdtree_get_pt(std::size_t i, std::size_t d) const { return centroids(static_cast<Eigen::Index>(d), static_cast<Eigen::Index>(i)); }
  template <class Box>
  bool kdtree_get_bbox(Box&) const { return false; }
};
using CentroidTree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, CentroidCloud>, CentroidCloud, 3>;

/// Euclidean distance from p to tet t (zero when a barycentric coordinate check says inside).
double distanceToTet(const TetMesh& mesh, Eigen::Index t, const Eigen::Vector4d& w, const Eigen::Vector3d& p) {
  if (w.minCoeff() >= 0.0) return 0.0;
  double distance = std::numeric_limits<double>::infinity();
  for (int skip = 0; skip < 4; ++skip) {
    Eigen::Vector3d corner[3];
    for (int c = 0, k = 0; c < 4; ++c)
      if (c != skip) corner[k++] = mesh.vertices.col(mesh.tets(c, t));
    distance = std::min(distance, (closestPointOnTriangle(p, corner[0], corner[1], corner[2]) - p).norm());
  }
  return distance;
}

}  // namespace

Eigen::Vector4d barycentricCoordinates(const TetMesh& mesh, Eigen::Index t, const Eigen::Vector3d& p) {
  const Eigen::Vector3d x0 = mesh.vertices.col(mesh.tets(0, t));
  Eigen::Matrix3d edges;
  for (int c = 0; c < 3; ++c) edges.col(c) = mesh.vertices.col(mesh.tets(c + 1, t)) - x0;
  // p = x0 + edges * (w1, w2, w3), w0 = 1 - w1 - w2 - w3.
  const Eigen::Vector3d w = edges.partialPivLu().solve(p - x0);
  return Eigen::Vector4d(1.0 - w.sum(), w[0], w[1], w[2]);
}

namespace {

/// The tet nearest to p among the candidates and its barycentric coordinates (distance 0 when inside).
struct NearestTet {
  Eigen::Index tet = -1;
  Eigen::Vector4d weights = Eigen::Vector4d::Zero();
  double distance = std::numeric_limits<double>::infinity();
};

template <class Candidates>
NearestTet nearestOf(const TetMesh& mesh, const Eigen::Vector3d& p, const Candidates& candidates) {
  NearestTet best;
  for (const Eigen::Index t : candidates) {
    const Eigen::Vector4d w = barycentricCoordinates(mesh, t, p);
    const double d = distanceToTet(mesh, t, w, p);
    if (d < best.distance) best = {t, w, d};
    if (best.distance == 0.0) break;
  }
  return best;
}

/// A distance for messages: three significant digits ("0.00213 m").
std::string metres(double value) {
  std::ostringstream text;
  text << std::setprecision(3) << value << " m";
  return text.str();
}

/// The refusal: how many points are too far, and the farthest one's exact distance (brute force over
/// all tets, for that one point only: the search gives an upper bound beyond maxOutside).
[[noreturn]] void refuseFarPoints(const TetMesh& coarse, const Eigen::Matrix3Xd& points, Eigen::Index tooFar,
                                  Eigen::Index farthest, double maxOutside) {
  std::vector<Eigen::Index> all(static_cast<size_t>(coarse.numTets()));
  for (Eigen::Index t = 0; t < coarse.numTets(); ++t) all[static_cast<size_t>(t)] = t;
  const double distance = nearestOf(coarse, points.col(farthest), all).distance;
  throw InvalidInputError("embedPoints: " + std::to_string(tooFar) + " of " + std::to_string(points.cols()) +
                          " points are farther than " + metres(maxOutside) +
                          " from the coarse mesh; the farthest, point " + std::to_string(farthest) + ", is " +
                          metres(distance) + " away");
}

EmbeddingReport reportOf(const Eigen::VectorXd& outside, const TetMesh& coarse) {
  const double tolerance =
      1e-9 * (coarse.vertices.rowwise().maxCoeff() - coarse.vertices.rowwise().minCoeff()).norm();
  EmbeddingReport report;
  double sum = 0.0;
  for (Eigen::Index i = 0; i < outside.size(); ++i) {
    if (std::isinf(outside[i])) continue;  // left out
    report.maxDistance = std::max(report.maxDistance, outside[i]);
    if (outside[i] > tolerance) {
      ++report.outside;
      sum += outside[i];
    }
  }
  if (report.outside > 0) report.meanDistance = sum / static_cast<double>(report.outside);
  return report;
}

}  // namespace

BarycentricEmbedding embedPoints(const TetMesh& coarse, const Eigen::Matrix3Xd& points, double maxOutside, FarPoints far) {
  validate(coarse);
  if (!points.allFinite()) throw InvalidInputError("embedPoints: points contain NaN or Inf");
  if (!(maxOutside >= 0.0)) throw InvalidInputError("embedPoints: maxOutside must be non-negative");
  const Eigen::Index tetCount = coarse.numTets();
  Eigen::Matrix3Xd centroids(3, tetCount);
  double searchRadius = 0.0;  // largest centroid-to-corner distance: any containing tet's centroid is this close
  for (Eigen::Index t = 0; t < tetCount; ++t) {
    centroids.col(t).setZero();
    for (int c = 0; c < 4; ++c) centroids.col(t) += 0.25 * coarse.vertices.col(coarse.tets(c, t));
    for (int c = 0; c < 4; ++c)
      searchRadius = std::max(searchRadius, (coarse.vertices.col(coarse.tets(c, t)) - centroids.col(t)).norm());
  }
  CentroidCloud cloud{centroids};
  CentroidTree tree(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(10));
  tree.buildIndex();

  BarycentricEmbedding embedding;
  embedding.tet.resize(points.cols());
  embedding.weights.resize(4, points.cols());
  embedding.outside.resize(points.cols());
  std::vector<std::pair<unsigned int, double>> hits;
  std::vector<Eigen::Index> candidates;
  const nanoflann::SearchParams params(32, 0.0, false);
  Eigen::Index tooFar = 0, farthest = -1;
  for (Eigen::Index i = 0; i < points.cols(); ++i) {
    const Eigen::Vector3d p = points.col(i);
    // Candidates: every tet whose centroid is within reach of p (so every tet within maxOutside of p);
    // when there are none (p lies farther out), the nearest centroids, for the message.
    const double radius = searchRadius + maxOutside;
    tree.radiusSearch(p.data(), radius * radius, hits, params);
    if (hits.empty() && far == FarPoints::Skip) {
      embedding.tet[i] = -1;
      embedding.weights.col(i).setZero();
      embedding.outside[i] = std::numeric_limits<double>::infinity();
      continue;
    }
    if (hits.empty()) {
      std::vector<unsigned int> index(8);
      std::vector<double> distance(8);
      const std::size_t found = tree.knnSearch(p.data(), index.size(), index.data(), distance.data());
      for (std::size_t k = 0; k < found; ++k) hits.emplace_back(index[k], distance[k]);
    }
    candidates.clear();
    for (const auto& hit : hits) candidates.push_back(hit.first);
    // Inside some tet: take it. Otherwise the nearest tet; its barycentric coordinates (slightly
    // negative) extend that tet's affine interpolant, which keeps affine fields exact.
    NearestTet nearest = nearestOf(coarse, p, candidates);
    if (nearest.distance > maxOutside && far == FarPoints::Skip) nearest = NearestTet{-1, Eigen::Vector4d::Zero(), nearest.distance};
    else if (nearest.distance > maxOutside) {
      if (farthest < 0 || nearest.distance > embedding.outside[farthest]) farthest = i;
      ++tooFar;
    }
    embedding.tet[i] = static_cast<int>(nearest.tet);
    embedding.weights.col(i) = nearest.weights;
    embedding.outside[i] = nearest.distance;
  }
  if (tooFar > 0) refuseFarPoints(coarse, points, tooFar, farthest, maxOutside);
  embedding.report = reportOf(embedding.outside, coarse);
  return embedding;
}

std::string describe(const EmbeddingReport& report, Eigen::Index points) {
  std::string text = std::to_string(report.outside) + " of " + std::to_string(points) + " points outside the coarse mesh";
  if (report.outside > 0)
    text += ", up to " + metres(report.maxDistance) + " (mean " + metres(report.meanDistance) + ")";
  return text;
}

Eigen::Matrix3Xd interpolate(const BarycentricEmbedding& embedding, const TetMesh& coarse, const Eigen::Matrix3Xd& field) {
  if (field.cols() != coarse.numVertices())
    throw InvalidInputError("interpolate: field has " + std::to_string(field.cols()) + " columns for " +
                            std::to_string(coarse.numVertices()) + " coarse vertices");
  if (!field.allFinite()) throw InvalidInputError("interpolate: field contains NaN or Inf");
  if (embedding.weights.cols() != embedding.tet.size())
    throw InvalidInputError("interpolate: embedding tet and weight counts differ");
  Eigen::Matrix3Xd result(3, embedding.tet.size());
  for (Eigen::Index i = 0; i < embedding.tet.size(); ++i) {
    const int t = embedding.tet[i];
    result.col(i).setZero();
    if (t == -1) continue;  // left out (FarPoints::Skip)
    if (t < 0 || t >= coarse.numTets()) throw InvalidInputError("interpolate: embedding references a missing tet");
    for (int c = 0; c < 4; ++c) result.col(i) += embedding.weights(c, i) * field.col(coarse.tets(c, t));
  }
  return result;
}

}  // namespace deformation_enrichment::mesh
