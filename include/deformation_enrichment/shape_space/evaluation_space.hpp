#pragma once
// Where the reduced solvers evaluate the energy ([Brandt16 §6], "Energy and force approximation"): on the
// fine mesh, or on a ghost mesh (ghost_mesh.hpp) of a reference shape whose vertices are a subset of the
// fine ones, so that the fine shape o + B q and the ghost shape S o + (S B) q share the reduced coordinates
// q. Set up once, from the reduction options, by the smoothing flow and the geodesic solvers.
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "deformation_enrichment/shape_space/deformation_energy.hpp"
#include "deformation_enrichment/shape_space/ghost_mesh.hpp"

namespace deformation_enrichment::shape_space {

struct ReductionOptions {
  bool reduced = false;        ///< reduced (subspace) solvers instead of full-space Newton
  int subspaceDimension = 16;  ///< PCA directions of the sequence (reduced mode)
  /// Reduced mode: evaluate energies and gradients on a ghost mesh of the first shape when the mesh has more
  /// than ghostMesh.targetVertices vertices; the shapes stay fine (same reduced coordinates).
  bool useGhostMesh = true;
  GhostMeshOptions ghostMesh;
};

class EvaluationSpace {
public:
  /// The fine energy, or (reduced mode with a ghost mesh wanted and the mesh larger than its target) the
  /// ghost mesh of `reference` with the same energy on it. Throws InvalidInputError as ghostMesh() does
  /// (e.g. for a non-manifold mesh) and for a subspace dimension below 1.
  EvaluationSpace(const DeformationEnergy& fine, const Eigen::Matrix3Xi& triangles, const Eigen::VectorXd& reference,
                  const ReductionOptions& options);

  /// The energy the solvers evaluate (the ghost's, or the fine one).
  const DeformationEnergy& energy() const { return ghostEnergy_ ? *ghostEnergy_ : fine_; }
  const DeformationEnergy& fineEnergy() const { return fine_; }
  const GhostMesh* ghost() const { return ghost_.get(); }
  /// Vertices of the ghost mesh (0: none).
  Eigen::Index ghostVertices() const { return ghost_ ? ghost_->numVertices() : 0; }

  /// S y: the evaluated shape of a fine one (a copy of it without a ghost mesh).
  Eigen::VectorXd restrict(const Eigen::VectorXd& fine) const { return ghost_ ? ghost_->restrict(fine) : fine; }
  /// S B: the evaluated rows of a fine basis.
  Eigen::MatrixXd restrictRows(const Eigen::MatrixXd& fine) const { return ghost_ ? ghost_->restrictRows(fine) : fine; }
  /// The evaluated shapes: `fine` itself without a ghost mesh, else their restrictions, kept in `storage`.
  const std::vector<Eigen::VectorXd>& restrict(const std::vector<Eigen::VectorXd>& fine,
                                               std::vector<Eigen::VectorXd>& storage) const;

private:
  const DeformationEnergy& fine_;
  std::unique_ptr<GhostMesh> ghost_;
  std::unique_ptr<DeformationEnergy> ghostEnergy_;
};

}  // namespace deformation_enrichment::shape_space
