#include "deformation_enrichment/mesh/barycentric_embedding.hpp"

#include <Eigen/Dense>
#include <nanoflann.hpp>
#include <limits>
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

BarycentricEmbedding embedPoints(const TetMesh& coarse, const Eigen::Matrix3Xd& points, double maxOutside) {
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
  const nanoflann::SearchParams params(32, 0.0, false);
  for (Eigen::Index i = 0; i < points.cols(); ++i) {
    const Eigen::Vector3d p = points.col(i);
    // Candidates: every tet whose centroid is within reach of p (plus a margin for points just outside);
    // when there are none (p lies outside), fall back to the nearest centroids.
    const double radius = searchRadius + maxOutside;
    tree.radiusSearch(p.data(), radius * radius, hits, params);
    if (hits.empty()) {
      std::vector<unsigned int> index(8);
      std::vector<double> distance(8);
      const std::size_t found = tree.knnSearch(p.data(), index.size(), index.data(), distance.data());
      for (std::size_t k = 0; k < found; ++k) hits.emplace_back(index[k], distance[k]);
    }
    // Inside some tet: take it. Otherwise take the nearest tet; its barycentric coordinates (slightly
    // negative) extend that tet's affine interpolant, which keeps affine fields exact.
    Eigen::Index best = -1;
    Eigen::Vector4d bestWeights = Eigen::Vector4d::Zero();
    double distance = std::numeric_limits<double>::infinity();
    for (const auto& hit : hits) {
      const Eigen::Vector4d w = barycentricCoordinates(coarse, hit.first, p);
      const double d = distanceToTet(coarse, hit.first, w, p);
      if (d < distance) {
        distance = d;
        best = hit.first;
        bestWeights = w;
      }
      if (distance == 0.0) break;
    }
    if (distance > maxOutside)
      throw InvalidInputError("embedPoints: point " + std::to_string(i) + " is " + std::to_string(distance) +
                              " m outside the coarse mesh (limit " + std::to_string(maxOutside) + " m)");
    embedding.tet[i] = static_cast<int>(best);
    embedding.weights.col(i) = bestWeights;
    embedding.outside[i] = distance;
  }
  return embedding;
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
    if (t < 0 || t >= coarse.numTets()) throw InvalidInputError("interpolate: embedding references a missing tet");
    result.col(i).setZero();
    for (int c = 0; c < 4; ++c) result.col(i) += embedding.weights(c, i) * field.col(coarse.tets(c, t));
  }
  return result;
}

}  // namespace deformation_enrichment::mesh
