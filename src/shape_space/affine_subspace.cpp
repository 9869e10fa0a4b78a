#include "deformation_enrichment/shape_space/affine_subspace.hpp"

#include <string>

#include <Eigen/SVD>

#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::shape_space {

AffineSubspace pcaSubspace(const std::vector<Eigen::VectorXd>& shapes, int dimension, double relTol) {
  if (shapes.empty()) throw InvalidInputError("PCA subspace of an empty shape set");
  if (dimension < 1) throw InvalidInputError("PCA subspace dimension must be >= 1, got " + std::to_string(dimension));
  const Eigen::Index n = shapes.front().size();
  if (n == 0) throw InvalidInputError("PCA subspace of empty shapes");
  Eigen::MatrixXd centered(n, Eigen::Index(shapes.size()));
  for (size_t i = 0; i < shapes.size(); ++i) {
    if (shapes[i].size() != n) throw InvalidInputError("PCA subspace: shape " + std::to_string(i) + " has a different size");
    if (!shapes[i].allFinite()) throw InvalidInputError("PCA subspace: shape " + std::to_string(i) + " is not finite");
    centered.col(Eigen::Index(i)) = shapes[i];
  }
  AffineSubspace subspace;
  subspace.origin = centered.rowwise().mean();
  centered.colwise() -= subspace.origin;
  // Thin SVD of the n x m snapshot matrix (m small): left singular vectors are the principal directions.
  Eigen::BDCSVD<Eigen::MatrixXd> svd(centered, Eigen::ComputeThinU);
  const Eigen::VectorXd& sigma = svd.singularValues();
  Eigen::Index keep = 0;
  while (keep < sigma.size() && keep < dimension && sigma[keep] > relTol * std::max(sigma[0], 1e-300)) ++keep;
  subspace.basis = svd.matrixU().leftCols(keep);
  return subspace;
}

int enrich(AffineSubspace& subspace, const std::vector<Eigen::VectorXd>& directions, double relTol) {
  int added = 0;
  for (const Eigen::VectorXd& direction : directions) {
    if (direction.size() != subspace.origin.size())
      throw InvalidInputError("subspace enrichment direction has the wrong size");
    if (!direction.allFinite()) throw InvalidInputError("subspace enrichment direction is not finite");
    const double norm0 = direction.norm();
    if (norm0 == 0.0) continue;
    Eigen::VectorXd v = direction;
    for (int pass = 0; pass < 2; ++pass)  // re-orthogonalise once: classic remedy for Gram-Schmidt drift
      for (Eigen::Index c = 0; c < subspace.basis.cols(); ++c) v -= subspace.basis.col(c).dot(v) * subspace.basis.col(c);
    const double norm = v.norm();
    if (norm <= relTol * norm0) continue;
    subspace.basis.conservativeResize(subspace.origin.size(), subspace.basis.cols() + 1);
    subspace.basis.col(subspace.basis.cols() - 1) = v / norm;
    ++added;
  }
  return added;
}

}  // namespace deformation_enrichment::shape_space
