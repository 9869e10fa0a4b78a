#include "deformation_enrichment/shape_space/evaluation_space.hpp"

#include <string>

#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::shape_space {

EvaluationSpace::EvaluationSpace(const DeformationEnergy& fine, const Eigen::Matrix3Xi& triangles,
                                 const Eigen::VectorXd& reference, const ReductionOptions& options)
    : fine_(fine) {
  if (options.reduced && options.subspaceDimension < 1)
    throw InvalidInputError("reduced space: subspace dimension must be >= 1, got " + std::to_string(options.subspaceDimension));
  if (options.reduced && options.useGhostMesh && reference.size() / 3 > options.ghostMesh.targetVertices) {
    ghost_ = std::make_unique<GhostMesh>(ghostMesh(triangles, reference, options.ghostMesh));
    ghostEnergy_ = fine.onTriangles(ghost_->triangles, ghost_->numVertices());
  }
}

const std::vector<Eigen::VectorXd>& EvaluationSpace::restrict(const std::vector<Eigen::VectorXd>& fine,
                                                              std::vector<Eigen::VectorXd>& storage) const {
  if (!ghost_) return fine;
  storage.clear();
  storage.reserve(fine.size());
  for (const Eigen::VectorXd& x : fine) storage.push_back(ghost_->restrict(x));
  return storage;
}

}  // namespace deformation_enrichment::shape_space
