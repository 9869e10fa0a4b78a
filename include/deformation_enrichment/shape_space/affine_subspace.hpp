#pragma once
// Affine subspace y = origin + basis * q of R^n for the reduced smoothing flow ([Brandt16 §6],
// "Dimensional reduction"): the PCA span of the sequence, enriched by extra directions (a shape's own
// offset from the origin, flow tangents for short sequences). The basis is orthonormal.
#include <vector>

#include <Eigen/Core>

namespace deformation_enrichment::shape_space {

struct AffineSubspace {
  Eigen::VectorXd origin;  ///< n
  Eigen::MatrixXd basis;   ///< n x d, orthonormal columns

  Eigen::Index dimension() const { return basis.cols(); }
  Eigen::VectorXd lift(const Eigen::VectorXd& q) const { return origin + basis * q; }
  /// Coordinates of the orthogonal projection of y.
  Eigen::VectorXd coordinates(const Eigen::VectorXd& y) const { return basis.transpose() * (y - origin); }
};

/// Affine PCA subspace: origin = mean shape, basis = the leading `dimension` principal directions of the
/// shapes (fewer if the shapes span fewer; directions whose singular value is below relTol times the
/// largest are dropped). Throws InvalidInputError for an empty/ragged/non-finite set or dimension < 1.
AffineSubspace pcaSubspace(const std::vector<Eigen::VectorXd>& shapes, int dimension, double relTol = 1e-10);

/// Adds the components of `directions` orthogonal to the current basis (modified Gram-Schmidt, twice);
/// directions that are (numerically) already in the span are skipped. Returns how many were added.
int enrich(AffineSubspace& subspace, const std::vector<Eigen::VectorXd>& directions, double relTol = 1e-8);

}  // namespace deformation_enrichment::shape_space
