#pragma once
// Linear-tetrahedron finite elements of a hyperelastic body ([Masanti19] applied per tet): rest shape,
// per-tet Dm^-1 and rest volume, per-tet material (heterogeneous, e.g. stiff skin over soft bulk), and
// the assembled energy E(x) = sum_t V_t Psi_t(F_t), its gradient (minus the elastic forces) and its
// sparse (projected) Hessian. Degrees of freedom are ordered 3 v + i (vertex v, axis i).
//
// Assembly is parallel (OpenMP) and deterministic: blocks of consecutive tets are coloured so that no two
// blocks of one colour share a vertex, each colour is scattered in parallel without atomics, and every entry
// sums its tets' terms in the same order whatever the thread count and scheduling.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <vector>

#include "deformation_enrichment/elasticity/stable_neo_hookean.hpp"
#include "deformation_enrichment/mesh/tet_mesh.hpp"

namespace deformation_enrichment::elasticity {

enum class HessianKind { Exact, Projected };

class TetFem {
public:
  /// `materialId[t]` selects `materials[materialId[t]]` for tet t. Throws InvalidInputError for an
  /// invalid or degenerate (non-positive volume) rest mesh, no materials, or ids of the wrong size or range.
  TetFem(const mesh::TetMesh& rest, std::vector<StableNeoHookean> materials, const Eigen::VectorXi& materialId);
  /// Homogeneous body.
  TetFem(const mesh::TetMesh& rest, const StableNeoHookean& material);

  const mesh::TetMesh& rest() const { return rest_; }
  Eigen::Index numVertices() const { return rest_.numVertices(); }
  Eigen::Index numTets() const { return rest_.numTets(); }
  const Eigen::VectorXd& restVolumes() const { return restVolume_; }
  const Eigen::Matrix3d& restShapeInverse(Eigen::Index t) const { return dmInverse_[static_cast<std::size_t>(t)]; }
  const StableNeoHookean& material(Eigen::Index t) const { return materials_[static_cast<std::size_t>(materialId_[t])]; }
  /// Largest user mu over the materials (a stress scale for tolerances).
  double maxShearModulus() const;

  /// F_t = Ds(x) Dm^-1 with Ds = [x1 - x0, x2 - x0, x3 - x0], the constant deformation gradient of a linear
/// tet (written column-wise as in [Masanti19 eq. 2.1]).
  Eigen::Matrix3d deformationGradient(const Eigen::Matrix3Xd& x, Eigen::Index t) const;

  /// E(x) = sum_t V_t Psi(F_t). Returns +infinity (not an exception) for positions so extreme that a
  /// material rejects F (non-finite, |F|^2 > 1e60), so a line search can simply step back.
  /// Throws InvalidInputError if x has the wrong number of columns.
  double energy(const Eigen::Matrix3Xd& x) const;
  /// dE/dx (3V), sum_t V_t P(F_t) dF_t/dx.
  Eigen::VectorXd gradient(const Eigen::Matrix3Xd& x) const;
  /// Full symmetric 3V x 3V Hessian (both triangles stored).
  Eigen::SparseMatrix<double> hessian(const Eigen::Matrix3Xd& x, HessianKind kind = HessianKind::Projected) const;

  // Reduced assembly for constrained solvers. A dof map has 3V entries: the row of each dof in the
  // reduced system, or -1 for a constrained dof.
  /// Sparsity pattern (values zero) of the reduced Hessian; `lowerOnly` stores row >= column only.
  Eigen::SparseMatrix<double> reducedPattern(const Eigen::VectorXi& dofMap, bool lowerOnly) const;
  /// Overwrites the values of `H` (built by reducedPattern with the same map and `lowerOnly`) with the
  /// reduced Hessian at x and, when `gradient` is non-null, fills it with the reduced gradient.
  void assembleReduced(const Eigen::Matrix3Xd& x, const Eigen::VectorXi& dofMap, bool lowerOnly, HessianKind kind,
                       Eigen::SparseMatrix<double>& H, Eigen::VectorXd* gradient) const;

private:
  void checkPositions(const Eigen::Matrix3Xd& x, const char* where) const;
  /// dvec(F)/dx of tet t (9 x 12, constant per tet): entry (i + 3 j, 3 a + i) = G(a, j).
  Eigen::Matrix<double, 9, 12> shapeDerivative(Eigen::Index t) const;
  /// Calls visit(t) for every tet, colour by colour, the blocks of one colour in parallel on large meshes.
  template <class Visit>
  void forEachTetByColour(const Visit& visit) const;

  mesh::TetMesh rest_;
  std::vector<StableNeoHookean> materials_;
  Eigen::VectorXi materialId_;
  std::vector<Eigen::Matrix3d> dmInverse_;
  Eigen::VectorXd restVolume_;
  std::vector<Eigen::Index> blocksByColour_;  ///< tet block indices grouped by colour, increasing within a colour
  std::vector<std::size_t> colourStart_;      ///< colour c is blocksByColour_[colourStart_[c], colourStart_[c + 1])
};

/// Dof map for a body of `vertexCount` vertices whose listed vertices are constrained (all three axes):
/// free dofs are numbered in increasing global order. Throws InvalidInputError for out-of-range vertices.
Eigen::VectorXi makeDofMap(Eigen::Index vertexCount, const std::vector<int>& constrainedVertices, int* freeCount = nullptr);

}  // namespace deformation_enrichment::elasticity
