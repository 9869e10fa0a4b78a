#pragma once
// The weighted point set that discretises the material domain Omega for moment integrals ([Seiler14 eq. 8]):
// sample positions x_m with quadrature volumes V_m, plus a KD-tree (nanoflann) built once so that a
// window query touches only the points within the cut-off radius.
#include <Eigen/Core>
#include <memory>
#include <vector>

#include "deformation_enrichment/mesh/tet_mesh.hpp"

namespace deformation_enrichment::descriptors {

/// How window queries find their points: the KD-tree, or a brute-force scan (the benchmark baseline).
enum class NeighbourSearch { KdTree, BruteForce };

class PointSampling {
public:
  /// Takes the sample positions (3 x M) and their volumes (M, >= 0). Throws InvalidInputError for an empty
  /// set, mismatched sizes, non-finite positions or negative / non-finite volumes.
  PointSampling(Eigen::Matrix3Xd points, Eigen::VectorXd volumes);
  ~PointSampling();
  PointSampling(PointSampling&&) noexcept;
  PointSampling& operator=(PointSampling&&) noexcept;

  /// The tet mesh's vertices with lumped volumes (a quarter of every incident tet). Validates the mesh
  /// (degenerate tets -> InvalidInputError).
  static PointSampling fromTetMesh(const mesh::TetMesh& mesh);

  const Eigen::Matrix3Xd& points() const { return points_; }
  const Eigen::VectorXd& volumes() const { return volumes_; }
  Eigen::Index size() const { return points_.cols(); }

  /// Indices of all samples with |x_m - p| <= radius (unordered).
  void pointsWithin(const Eigen::Vector3d& p, double radius, std::vector<int>& indices,
                    NeighbourSearch search = NeighbourSearch::KdTree) const;

  /// Index of the sample nearest to p.
  int nearest(const Eigen::Vector3d& p) const;

private:
  struct Index;
  Eigen::Matrix3Xd points_;
  Eigen::VectorXd volumes_;
  std::unique_ptr<Index> index_;
};

}  // namespace deformation_enrichment::descriptors
