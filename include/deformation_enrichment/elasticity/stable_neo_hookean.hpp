#pragma once
// Stable Neo-Hookean hyperelasticity ([Smith18] as presented in [Masanti19]; docs/design.md §4).
//
// Two variants, both parametrised by the user's Lamé constants (mu, lambda) and reparametrised so that
// the Hessian at F = I equals the linear-elasticity tensor of (mu, lambda):
//   Paper:      Psi = mu'/2 (I_C - 3) + lambda'/2 (J - alpha)^2 - mu'/2 log(I_C + 1)   ([Masanti19 eq. 3.1])
//               mu' = 4/3 mu, lambda' = lambda + 5/6 mu, alpha = 1 + mu'/lambda' - mu'/(4 lambda').
//   Production: Psi = mu'/2 (I_C - 3) + lambda'/2 (J - alpha)^2
//               mu' = mu, lambda' = lambda + mu, alpha = 1 + mu'/lambda'.
// psi() returns Psi minus its (constant) rest value, so psi(I) = 0: energy differences in a line search
// then do not cancel against a large constant. PK1 and Hessians are unaffected by the shift.
//
// All 9x9 matrices act on the column-major vec(F) (entry r + 3 c holds F(r, c)).
#include <Eigen/Core>

#include "deformation_enrichment/elasticity/rotation_variant_svd.hpp"

namespace deformation_enrichment::elasticity {

using Matrix9d = Eigen::Matrix<double, 9, 9>;
using Vector9d = Eigen::Matrix<double, 9, 1>;

enum class SnhVariant { Paper, Production };

struct LameParameters {
  double mu;
  double lambda;
};

/// Lamé constants of Young's modulus E > 0 and Poisson ratio 0 < nu < 1/2:
/// mu = E / (2 (1 + nu)), lambda = E nu / ((1 + nu)(1 - 2 nu)). Throws InvalidInputError otherwise.
LameParameters lameFromYoungPoisson(double youngModulus, double poissonRatio);

/// (E, nu) of Lamé constants mu > 0, lambda > 0 (inverse of lameFromYoungPoisson).
void youngPoissonFromLame(const LameParameters& lame, double& youngModulus, double& poissonRatio);

/// The analytic eigensystem of the SNH Hessian at F ([Masanti19 §3.3]; [Smith18 §4]).
/// Columns of `vectors` are orthonormal eigenvectors on vec(F): 0..2 scaling modes, 3..5 twist modes,
/// 6..8 flip modes (mode 3 + k / 6 + k couples the singular directions other than k).
struct SnhEigensystem {
  Vector9d values;
  Matrix9d vectors;
};

class StableNeoHookean {
public:
  /// Throws InvalidInputError if mu or lambda is not finite or not positive.
  /// Every member taking F throws InvalidInputError if F has a non-finite entry or |F|_F^2 > 1e60
  /// (beyond that the Hessian terms would overflow).
  StableNeoHookean(double mu, double lambda, SnhVariant variant = SnhVariant::Paper);

  double psi(const Eigen::Matrix3d& F) const;
  /// First Piola-Kirchhoff stress dPsi/dF, written so that pk1(I) == 0 exactly.
  Eigen::Matrix3d pk1(const Eigen::Matrix3d& F) const;
  /// Exact Hessian d^2 Psi / d vec(F)^2 (may be indefinite).
  Matrix9d hessian(const Eigen::Matrix3d& F) const;
  /// Hessian with negative eigenvalues clamped to zero, assembled from the analytic eigensystem (twist and
  /// flip modes in closed form, 3x3 scaling block solved small; no 9x9 eigensolve). Symmetric PSD to
  /// rounding for every finite F, including F = 0, repeated or zero singular values and inversions.
  Matrix9d projectedHessian(const Eigen::Matrix3d& F) const;
  /// Same, reusing svd = rotationVariantSvd(F) that the caller already has (not re-checked).
  Matrix9d projectedHessian(const Eigen::Matrix3d& F, const RotationVariantSvd& svd) const;
  /// Full analytic eigensystem (for analysis and tests; the projection does not need the 9x9 vectors).
  SnhEigensystem eigensystem(const Eigen::Matrix3d& F) const;

  SnhVariant variant() const { return variant_; }
  double mu() const { return mu_; }                     ///< user's Lamé mu
  double lambda() const { return lambda_; }             ///< user's Lamé lambda
  double muPrime() const { return muPrime_; }           ///< reparametrised mu'
  double lambdaPrime() const { return lambdaPrime_; }   ///< reparametrised lambda'
  double alpha() const { return 1.0 + restShift_ / lambdaPrime_; }  ///< rest-stability shift of J

private:
  // Scalars shared by PK1, Hessian and eigensystem: Psi depends on F through I_C and J only.
  struct Coefficients {
    double a;  ///< coefficient of I_9 (Tikhonov term) and of F in PK1
    double b;  ///< coefficient of f f^T (Mu term)
    double s;  ///< lambda' (J - alpha): coefficient of cof F in PK1 and of the volume Hessian
  };
  Coefficients coefficients(double Ic, double J) const;
  /// Hessian block of the scaling modes in the basis vec(u_m v_m^T), m = 0..2.
  Eigen::Matrix3d scalingBlock(const Eigen::Vector3d& sigma, const Coefficients& k) const;
  void checkFinite(const Eigen::Matrix3d& F, const char* where) const;

  SnhVariant variant_;
  double mu_;
  double lambda_;
  double muPrime_;
  double lambdaPrime_;
  double restShift_;  ///< lambda' (alpha - 1): 3/4 mu' (Paper) or mu' (Production)
};

}  // namespace deformation_enrichment::elasticity
