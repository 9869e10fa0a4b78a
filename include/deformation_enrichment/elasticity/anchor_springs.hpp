#pragma once
// Zero-length penalty springs that pull vertices towards targets, E = 1/2 sum_i k_i |x_{v_i} - t_i|^2:
// a soft (penalty) alternative to Dirichlet constraints. A tool modelled this way loads the body with a
// weight that varies smoothly with the tool position, instead of switching whole vertices on and off.
#include <Eigen/Core>
#include <vector>

namespace deformation_enrichment::elasticity {

struct AnchorSprings {
  std::vector<int> vertices;   ///< distinct vertex indices
  Eigen::VectorXd stiffness;   ///< k_i (N/m), one per vertex, >= 0
  Eigen::Matrix3Xd targets;    ///< t_i, 3 x vertices.size()

  bool empty() const { return vertices.empty(); }
  /// Throws InvalidInputError naming the problem for mismatched sizes, out-of-range or repeated vertices,
  /// negative or non-finite stiffness, or non-finite targets.
  void validate(Eigen::Index vertexCount) const;
  /// E = 1/2 sum k_i |x_{v_i} - t_i|^2.
  double energy(const Eigen::Matrix3Xd& x) const;
  /// Adds dE/dx = k_i (x_{v_i} - t_i) to the 3V gradient `g` (dof 3 v + axis).
  void addGradient(const Eigen::Matrix3Xd& x, Eigen::VectorXd& g) const;
};

}  // namespace deformation_enrichment::elasticity
