#pragma once
// The compressible neo-Hookean solid of CalculiX's *HYPERELASTIC, NEO HOOKE ([Dhondt04]; the ABAQUS form),
// in our terms: Psi = mu/2 (J^(-2/3) I_C - 3) + kappa/2 (J - 1)^2 (C10 = mu/2, D1 = 2/kappa). Evaluated
// here only to tell how far CalculiX's answer is from equilibrium in its own energy, so that the part of a
// CalculiX-vs-SNH difference the two energy forms explain can be separated from solver error.
#include <Eigen/Core>
#include <vector>

#include "deformation_enrichment/elasticity/tet_fem.hpp"

namespace deformation_enrichment::elasticity {

class CompressibleNeoHookean {
public:
  /// Throws InvalidInputError unless mu and kappa are finite and positive.
  CompressibleNeoHookean(double mu, double kappa);

  /// Throws InvalidInputError for non-finite F or J <= 0 (the isochoric split needs J > 0).
  double psi(const Eigen::Matrix3d& F) const;
  /// P = mu J^(-2/3) (F - I_C/3 F^-T) + kappa (J - 1) J F^-T.
  Eigen::Matrix3d pk1(const Eigen::Matrix3d& F) const;

  double mu() const { return mu_; }
  double kappa() const { return kappa_; }

private:
  double mu_;
  double kappa_;
};

/// dE/dx (3V, dof 3 v + i) of E(x) = sum_t V_t Psi_{m(t)}(F_t) on the geometry of `fem` (rest volumes and
/// Dm^-1), tet t using materials[materialId[t]]. Throws InvalidInputError for sizes or ids that do not
/// match, or a tet with J <= 0 at x.
Eigen::VectorXd neoHookeanGradient(const TetFem& fem, const std::vector<CompressibleNeoHookean>& materials,
                                   const Eigen::VectorXi& materialId, const Eigen::Matrix3Xd& x);

}  // namespace deformation_enrichment::elasticity
