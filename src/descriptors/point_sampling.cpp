#include "deformation_enrichment/descriptors/point_sampling.hpp"

#include <cmath>
#include <nanoflann.hpp>
#include <string>

#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::descriptors {

namespace {
// nanoflann dataset adaptor over the columns of a 3 x M matrix (no copy).
struct ColumnCloud {
  const Eigen::Matrix3Xd* points;
  std::size_t kdtree_get_point_count() const { return static_cast<std::size_t>(points->cols()); }
  double kdtree_get_pt(std::size_t index, std::size_t dim) const {
    return (*points)(static_cast<Eigen::Index>(dim), static_cast<Eigen::Index>(index));
  }
  template <class Box>
  bool kdtree_get_bbox(Box&) const {
    return false;
  }
};
using KdTree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, ColumnCloud>,
                                                   ColumnCloud, 3, int>;
}  // namespace

struct PointSampling::Index {
  ColumnCloud cloud;
  KdTree tree;
  explicit Index(const Eigen::Matrix3Xd* points)
      : cloud{points}, tree(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(16)) {
    tree.buildIndex();
  }
};

PointSampling::PointSampling(Eigen::Matrix3Xd points, Eigen::VectorXd volumes)
    : points_(std::move(points)), volumes_(std::move(volumes)) {
  if (points_.cols() == 0) throw InvalidInputError("point sampling is empty");
  if (volumes_.size() != points_.cols())
    throw InvalidInputError("point sampling has " + std::to_string(points_.cols()) + " points but " +
                            std::to_string(volumes_.size()) + " volumes");
  for (Eigen::Index m = 0; m < points_.cols(); ++m) {
    if (!points_.col(m).allFinite())
      throw InvalidInputError("point sampling: point " + std::to_string(m) + " is not finite");
    if (!(volumes_[m] >= 0.0) || !std::isfinite(volumes_[m]))
      throw InvalidInputError("point sampling: volume of point " + std::to_string(m) +
                              " is negative or not finite");
  }
  // The tree keeps a pointer to points_, which stays put when *this is moved (Eigen moves the buffer).
  index_ = std::make_unique<Index>(&points_);
}

PointSampling::~PointSampling() = default;

PointSampling::PointSampling(PointSampling&& other) noexcept
    : points_(std::move(other.points_)), volumes_(std::move(other.volumes_)), index_(std::move(other.index_)) {
  if (index_) index_->cloud.points = &points_;
}

PointSampling& PointSampling::operator=(PointSampling&& other) noexcept {
  points_ = std::move(other.points_);
  volumes_ = std::move(other.volumes_);
  index_ = std::move(other.index_);
  if (index_) index_->cloud.points = &points_;
  return *this;
}

PointSampling PointSampling::fromTetMesh(const mesh::TetMesh& mesh) {
  mesh::validate(mesh, true);
  return PointSampling(mesh.vertices, mesh::lumpedVertexVolumes(mesh));
}

void PointSampling::pointsWithin(const Eigen::Vector3d& p, double radius, std::vector<int>& indices,
                                 NeighbourSearch search) const {
  if (!p.allFinite()) throw InvalidInputError("window centre is not finite");
  if (!(radius > 0.0) || !std::isfinite(radius))
    throw InvalidInputError("window radius " + std::to_string(radius) + " must be positive and finite");
  indices.clear();
  const double squaredRadius = radius * radius;
  if (search == NeighbourSearch::BruteForce) {
    for (Eigen::Index m = 0; m < points_.cols(); ++m)
      if ((points_.col(m) - p).squaredNorm() <= squaredRadius) indices.push_back(static_cast<int>(m));
    return;
  }
  std::vector<std::pair<int, double>> matches;
  nanoflann::SearchParams params;
  params.sorted = false;
  index_->tree.radiusSearch(p.data(), squaredRadius, matches, params);  // L2_Simple works on squared radii
  indices.reserve(matches.size());
  for (const auto& match : matches) indices.push_back(match.first);
}

int PointSampling::nearest(const Eigen::Vector3d& p) const {
  if (!p.allFinite()) throw InvalidInputError("query point is not finite");
  int index = 0;
  double squaredDistance = 0.0;
  nanoflann::KNNResultSet<double, int> result(1);
  result.init(&index, &squaredDistance);
  index_->tree.findNeighbors(result, p.data(), nanoflann::SearchParams());
  return index;
}

}  // namespace deformation_enrichment::descriptors
