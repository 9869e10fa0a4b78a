#pragma once
// Discrete Shells deformation energy W[x_bar, x] = membrane + k_bend * bending for triangle meshes of one
// fixed topology ([Brandt16 §3 and §7]; docs/design.md §4 "Shape space").
//
// Membrane (choose one):
//  - DiscreteShells ([Grinspun03]): k_L sum_e (1 - |e|/|e_bar|)^2 |e_bar| + k_A sum_t (1 - A/A_bar)^2 A_bar.
//  - Hyperelastic ([Heeren12 eq. 8], as in GOAST): sum_t A_bar W(tr G, det G), G = g_bar^-1 g,
//    W(a, d) = mu/2 a + lambda/4 d - (mu/2 + lambda/4) log d - mu - lambda/4.
// Bending: sum_e (theta_e - theta_bar_e)^2 c |e_bar|^2 / (A_bar_1 + A_bar_2), theta the dihedral angle;
//   c = 3 with the DiscreteShells membrane ([Grinspun03]'s |e_bar| / h_bar_e, h_bar_e a third of the average
//   height of the two triangles) and c = 1 with the Hyperelastic membrane (GOAST's SimpleBendingEnergy).
//
// Non-manifold input: only edges shared by exactly two triangles carry a bending term. Boundary edges (one
// triangle) and edges with three or more triangles (or two copies of one triangle) are skipped for bending
// (counted, see numBoundaryEdges / numNonManifoldEdges); every
// triangle and every distinct edge still carries its membrane term. Inconsistent triangle orientation is
// accepted: each hinge's angle is measured from its first triangle's winding. theta - theta_bar is taken
// modulo 2 pi (in [-pi, pi]), so a hinge folding through +-pi does not jump.
// A triangle whose area is below 1e-8 times its summed squared edge lengths, in either shape, is
// degenerate: every evaluation then throws InvalidInputError naming the triangle and the shape.
//
// Evaluations are const and keep no state, so several threads may evaluate one DiscreteShells at once (each
// call runs its own OpenMP loop over triangles, edges and hinges on meshes of >= 1000 vertices, serially on
// smaller ones; nested inside an outer parallel region it runs serially unless nesting is enabled). Hessians share one sparsity pattern (vertex pairs sharing a
// triangle or a hinge), so blocks from different calls add without reallocation.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <string>
#include <vector>

#include "deformation_enrichment/shape_space/deformation_energy.hpp"

namespace deformation_enrichment::shape_space {

enum class MembraneModel { DiscreteShells, Hyperelastic };

namespace detail {
class ShellPathTerms;  // the module's per-shape element data and eq. 4 segment terms (private)

/// Fixed sparsity of the Hessian blocks: vertex pairs that share a triangle or a hinge (built once).
struct HessianPattern {
  std::vector<int> neighbourStart;  ///< per vertex, range into neighbours (size V + 1)
  std::vector<int> neighbours;      ///< sorted neighbour vertices, each vertex included in its own list
  std::vector<int> outer;           ///< compressed column starts of zeros (size 3V + 1)
  Eigen::SparseMatrix<double> zeros;  ///< 3V x 3V, the pattern with zero values
};
}  // namespace detail

struct DiscreteShellsOptions {
  MembraneModel membrane = MembraneModel::Hyperelastic;
  double lengthWeight = 0.5;  ///< k_L (DiscreteShells membrane only)
  double areaWeight = 0.5;    ///< k_A (DiscreteShells membrane only)
  double mu = 1.0;            ///< Lame mu (Hyperelastic membrane only)
  double lambda = 1.0;        ///< Lame lambda (Hyperelastic membrane only)
  double bendingWeight = 1e-3;  ///< k_B (DiscreteShells) or delta (Hyperelastic)

  /// Paper 004 §7: k_B = 1, k_L = k_A = 1/2.
  static DiscreteShellsOptions classic();
  /// GOAST's shell energy: mu = lambda = 1, bending weighted by delta.
  static DiscreteShellsOptions hyperelastic(double delta = 1e-3);
  /// GOAST's shell energy with delta for the size of `shape` (flat 3V, bounding-box diagonal D): the
  /// membrane grows with the area and the bending term does not (delta is a squared thickness), so GOAST's
  /// delta = 1e-3 on the finger (D = 5.1313) becomes 1e-3 (D / 5.1313)^2, the same relative thickness (0.14
  /// on the MD2 models, where 1e-3 left hinges free to flap and noisy clips got rougher vertex trajectories).
  /// Throws InvalidInputError for an empty, non-finite or single-point shape.
  static DiscreteShellsOptions hyperelasticFor(const Eigen::VectorXd& shape);
};

class DiscreteShells final : public DeformationEnergy {
public:
  /// triangles: 3 x T vertex indices into numVertices vertices. Throws InvalidInputError on an empty mesh,
  /// out-of-range or repeated indices, or non-finite / negative parameters.
  DiscreteShells(const Eigen::Matrix3Xi& triangles, Eigen::Index numVertices,
                 const DiscreteShellsOptions& parameters = DiscreteShellsOptions::hyperelastic());

  Eigen::Index numVertices() const override { return numVertices_; }
  /// Size, finite entries and no degenerate triangle (see the header comment).
  void checkShape(const Eigen::VectorXd& shape) const override;
  /// Several outputs (the non-null members of `outputs`) in one pass over the mesh.
  void evaluate(const Eigen::VectorXd& reference, const Eigen::VectorXd& deformed,
                const EnergyOutputs& outputs) const override;

  /// eq. 4's segment terms from each shape's element data (edge lengths, areas, dihedral angles, hinge weights
  /// and their derivatives), computed once per shape and shared by both directions of both its segments
  /// (discrete_shells_path.cpp); shapes in parallel on meshes of >= 1000 vertices. Same errors as evaluate.
  std::vector<double> pathSegments(const std::vector<Eigen::VectorXd>& shapes, bool closed,
                                   std::vector<Eigen::VectorXd>* gradients, bool endGradients) const override;

  /// DiscreteShells with the same parameters and thread count over `triangles`.
  std::unique_ptr<DeformationEnergy> onTriangles(const Eigen::Matrix3Xi& triangles, Eigen::Index numVertices) const override;

  /// sum_i w_i W[x_i, .] in one pass per evaluation (discrete_shells_average.cpp): every term is linear in
  /// per-element reference data (see there), so the examples aggregate into one effective reference.
  /// Value, gradient and Hessian in one deformed-only pass each. Throws InvalidInputError for mismatched sizes, negative or non-finite
  /// weights, or non-finite or degenerate references.
  /// `data` as referenceData() makes it: per face the squared edge lengths and area, per hinge the angle and
  /// weight, per edge (classic membrane) the length.
  using DeformationEnergy::weightedReferences;
  std::unique_ptr<WeightedReferenceEnergy> weightedReferences(const std::vector<double>& weights,
                                                              const std::vector<const Eigen::VectorXd*>& references,
                                                              const std::vector<const ReferenceData*>& data) const override;
  std::shared_ptr<const ReferenceData> referenceData(const Eigen::VectorXd& shape) const override;
  /// Eq. 4 from referenceData() of every path shape: the segment terms of pathSegments from the kept element
  /// data, no pass over a shape (segments in parallel as pathSegments'). Throws InvalidInputError for fewer
  /// than 2 shapes or data not made by this energy.
  std::optional<double> pathEnergy(const std::vector<const ReferenceData*>& data, bool closed) const override;

  /// Membrane and bending parts separately (bending already multiplied by bendingWeight).
  double membraneValue(const Eigen::VectorXd& reference, const Eigen::VectorXd& deformed) const;
  double bendingValue(const Eigen::VectorXd& reference, const Eigen::VectorXd& deformed) const;

  /// OpenMP threads used by evaluations (1 = serial). Defaults to the OpenMP maximum.
  void setThreadCount(int threads);
  int threadCount() const { return threads_; }

  const DiscreteShellsOptions& parameters() const { return parameters_; }
  Eigen::Index numTriangles() const { return triangles_.cols(); }
  const Eigen::Matrix3Xi& triangles() const { return triangles_; }
  const std::vector<Eigen::Vector2i>& edges() const { return edges_; }
  /// (i, j, k, l): edge i -> j as in triangle (i, j, k), l the opposite corner of the other triangle.
  const std::vector<Eigen::Vector4i>& hinges() const { return hinges_; }
  Eigen::Index numEdges() const { return static_cast<Eigen::Index>(edges_.size()); }
  Eigen::Index numHinges() const { return static_cast<Eigen::Index>(hinges_.size()); }
  Eigen::Index numBoundaryEdges() const { return numBoundaryEdges_; }
  /// The sparsity of every Hessian block (and of weightedReferences' Hessians).
  const detail::HessianPattern& hessianPattern() const { return pattern_; }
  Eigen::Index numNonManifoldEdges() const { return numNonManifoldEdges_; }

private:
  enum Parts : unsigned { kMembrane = 1u, kBending = 2u };
  /// The requested outputs of the given parts (OR of Parts) in one pass.
  void assemble(const Eigen::VectorXd& reference, const Eigen::VectorXd& deformed, const EnergyOutputs& outputs,
                unsigned parts) const;
  /// The value of a pass over `parts` alone.
  double partsValue(const Eigen::VectorXd& reference, const Eigen::VectorXd& deformed, unsigned parts) const;
  void checkTriangles(const Eigen::VectorXd& shape, const char* name) const;
  /// Throws InvalidInputError naming triangle t of `shape` (e.g. "the deformed shape").
  [[noreturn]] void throwDegenerate(Eigen::Index t, const std::string& shape, double area) const;
  friend class detail::ShellPathTerms;  // pathSegments' per-shape data and segment terms
  void buildHessianPattern();

  Eigen::Matrix3Xi triangles_;
  Eigen::Index numVertices_ = 0;
  DiscreteShellsOptions parameters_;
  std::vector<Eigen::Vector2i> edges_;   ///< distinct edges (membrane length term)
  std::vector<Eigen::Vector4i> hinges_;  ///< (i, j, k, l): edge i -> j as in triangle (i, j, k), l opposite
  Eigen::Index numBoundaryEdges_ = 0;
  Eigen::Index numNonManifoldEdges_ = 0;
  detail::HessianPattern pattern_;
  int threads_ = 1;
};

}  // namespace deformation_enrichment::shape_space
