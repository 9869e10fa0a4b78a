#include "deformation_enrichment/elasticity/stable_neo_hookean.hpp"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <string>

#include "deformation_enrichment/elasticity/symmetric_eigen3.hpp"
#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::elasticity {

namespace {

constexpr double kMaxIc = 1e60;  // |F|_F^2 beyond which (lambda' g g^T) could overflow

// Columns of cof F = dJ/dF = [f1 x f2 | f2 x f0 | f0 x f1] ([Masanti19 eq. 3.2]).
Eigen::Matrix3d cofactor(const Eigen::Matrix3d& F) {
  Eigen::Matrix3d g;
  g.col(0) = F.col(1).cross(F.col(2));
  g.col(1) = F.col(2).cross(F.col(0));
  g.col(2) = F.col(0).cross(F.col(1));
  return g;
}

// Cross-product matrix x^ with x^ y = x × y.
Eigen::Matrix3d hat(const Eigen::Vector3d& x) {
  Eigen::Matrix3d m;
  m << 0.0, -x(2), x(1),  //
      x(2), 0.0, -x(0),   //
      -x(1), x(0), 0.0;
  return m;
}

// vec(u_i v_j^T) on column-major vec: entry r + 3 c = U(r, i) V(c, j).
Vector9d outerVec(const Eigen::Matrix3d& U, int i, const Eigen::Matrix3d& V, int j) {
  Vector9d w;
  for (int c = 0; c < 3; ++c) w.segment<3>(3 * c) = V(c, j) * U.col(i);
  return w;
}

// Pairs (i, j) of singular directions coupled by twist/flip mode k (the remaining direction).
constexpr int kPairI[3] = {1, 2, 0};
constexpr int kPairJ[3] = {2, 0, 1};

}  // namespace

LameParameters lameFromYoungPoisson(double youngModulus, double poissonRatio) {
  if (!std::isfinite(youngModulus) || youngModulus <= 0.0) {
    throw InvalidInputError("lameFromYoungPoisson: Young's modulus must be finite and positive, got " +
                            std::to_string(youngModulus));
  }
  if (!std::isfinite(poissonRatio) || poissonRatio <= 0.0 || poissonRatio >= 0.5) {
    throw InvalidInputError("lameFromYoungPoisson: Poisson ratio must lie in (0, 0.5), got " +
                            std::to_string(poissonRatio));
  }
  const double mu = youngModulus / (2.0 * (1.0 + poissonRatio));
  const double lambda = youngModulus * poissonRatio / ((1.0 + poissonRatio) * (1.0 - 2.0 * poissonRatio));
  return {mu, lambda};
}

void youngPoissonFromLame(const LameParameters& lame, double& youngModulus, double& poissonRatio) {
  if (!std::isfinite(lame.mu) || !std::isfinite(lame.lambda) || lame.mu <= 0.0 || lame.lambda <= 0.0) {
    throw InvalidInputError("youngPoissonFromLame: mu and lambda must be finite and positive");
  }
  youngModulus = lame.mu * (3.0 * lame.lambda + 2.0 * lame.mu) / (lame.lambda + lame.mu);
  poissonRatio = lame.lambda / (2.0 * (lame.lambda + lame.mu));
}

StableNeoHookean::StableNeoHookean(double mu, double lambda, SnhVariant variant)
    : variant_(variant), mu_(mu), lambda_(lambda) {
  if (!std::isfinite(mu) || mu <= 0.0) {
    throw InvalidInputError("StableNeoHookean: mu must be finite and positive, got " + std::to_string(mu));
  }
  if (!std::isfinite(lambda) || lambda <= 0.0) {
    throw InvalidInputError("StableNeoHookean: lambda must be finite and positive, got " +
                            std::to_string(lambda));
  }
  if (variant == SnhVariant::Paper) {
    // Reparametrisation matching linear elasticity at F = I ([Smith18 §3.4], [Masanti19 eq. 3.1]).
    muPrime_ = 4.0 / 3.0 * mu;
    lambdaPrime_ = lambda + 5.0 / 6.0 * mu;
    restShift_ = 0.75 * muPrime_;  // lambda'(alpha - 1) with alpha = 1 + mu'/lambda' - mu'/(4 lambda')
  } else {
    muPrime_ = mu;
    lambdaPrime_ = lambda + mu;
    restShift_ = muPrime_;  // lambda'(alpha - 1) with alpha = 1 + mu'/lambda'
  }
}

void StableNeoHookean::checkFinite(const Eigen::Matrix3d& F, const char* where) const {
  if (!F.allFinite()) {
    throw InvalidInputError(std::string("StableNeoHookean::") + where +
                            ": deformation gradient has a non-finite entry");
  }
  if (F.squaredNorm() > kMaxIc) {
    throw InvalidInputError(std::string("StableNeoHookean::") + where +
                            ": deformation gradient too large (|F|^2 > 1e60)");
  }
}

StableNeoHookean::Coefficients StableNeoHookean::coefficients(double Ic, double J) const {
  // s = lambda'(J - alpha) = lambda'(J - 1) - lambda'(alpha - 1): exactly 0 - restShift at J = 1.
  const double s = lambdaPrime_ * (J - 1.0) - restShift_;
  if (variant_ == SnhVariant::Production) return {muPrime_, 0.0, s};
  const double inv = 1.0 / (Ic + 1.0);
  // PK1 = mu'(1 - 1/(I_C+1)) F + lambda'(J - alpha) dJ/dF; its derivative adds 2 mu'/(I_C+1)^2 f f^T.
  return {muPrime_ * (1.0 - inv), 2.0 * muPrime_ * inv * inv, s};
}

double StableNeoHookean::psi(const Eigen::Matrix3d& F) const {
  checkFinite(F, "psi");
  // I_C - 3 = |F - I|^2 + 2 tr(F - I) avoids cancellation near rest.
  const Eigen::Matrix3d E = F - Eigen::Matrix3d::Identity();
  const double icMinus3 = E.squaredNorm() + 2.0 * E.trace();
  const double jMinus1 = F.determinant() - 1.0;
  // lambda'/2 [(J - alpha)^2 - (1 - alpha)^2] = (J - 1)(lambda'(J - 1)/2 - lambda'(alpha - 1)).
  double value = 0.5 * muPrime_ * icMinus3 + jMinus1 * (0.5 * lambdaPrime_ * jMinus1 - restShift_);
  if (variant_ == SnhVariant::Paper) {
    // -mu'/2 [log(I_C + 1) - log 4] (eq. 3.1 log term, shifted to vanish at rest).
    value -= 0.5 * muPrime_ * std::log1p(0.25 * icMinus3);
  }
  return value;
}

Eigen::Matrix3d StableNeoHookean::pk1(const Eigen::Matrix3d& F) const {
  checkFinite(F, "pk1");
  const Eigen::Matrix3d g = cofactor(F);
  const double J = F.col(0).dot(g.col(0));
  const Coefficients k = coefficients(F.squaredNorm(), J);
  // P = a F + lambda'(J - alpha) cof F ([Masanti19] eq. after 3.1). At F = I: a = 3/4 mu' = restShift (Paper)
  // or mu' (Production) bit for bit, and J - 1 = 0, so P(I) = 0 exactly.
  return k.a * F + k.s * g;
}

Matrix9d StableNeoHookean::hessian(const Eigen::Matrix3d& F) const {
  checkFinite(F, "hessian");
  const Eigen::Matrix3d g = cofactor(F);
  const double J = F.col(0).dot(g.col(0));
  const Coefficients k = coefficients(F.squaredNorm(), J);
  const Eigen::Map<const Vector9d> f(F.data());
  const Eigen::Map<const Vector9d> gv(g.data());
  // H = T + M + G + H_J ([Masanti19 §3.3.2]): a I + b f f^T + lambda' g g^T + lambda'(J - alpha) d^2J/dF^2.
  Matrix9d H = k.b * f * f.transpose() + lambdaPrime_ * gv * gv.transpose();
  H.diagonal().array() += k.a;
  // Volume Hessian: self-similar cross-product matrix of the columns of F ([Masanti19 §3.3.4]).
  const Eigen::Matrix3d h0 = k.s * hat(F.col(0));
  const Eigen::Matrix3d h1 = k.s * hat(F.col(1));
  const Eigen::Matrix3d h2 = k.s * hat(F.col(2));
  H.block<3, 3>(0, 3) -= h2;
  H.block<3, 3>(0, 6) += h1;
  H.block<3, 3>(3, 0) += h2;
  H.block<3, 3>(3, 6) -= h0;
  H.block<3, 3>(6, 0) -= h1;
  H.block<3, 3>(6, 3) += h0;
  return H;
}

Eigen::Matrix3d StableNeoHookean::scalingBlock(const Eigen::Vector3d& sig, const Coefficients& k) const {
  // The Hessian restricted to D = diag(d): a I + b sigma sigma^T + lambda' c c^T + lambda'(J - alpha) S,
  // with c = dJ/dsigma = (s1 s2, s0 s2, s0 s1) and S_ij = sigma_k (i != j), the volume Hessian's diagonal
  // part, since d^2 det(Sigma + D) = 2 sum_{i<j} sigma_k (d_i d_j - D_ij D_ji).
  const Eigen::Vector3d c(sig(1) * sig(2), sig(0) * sig(2), sig(0) * sig(1));
  Eigen::Matrix3d A = k.b * sig * sig.transpose() + lambdaPrime_ * c * c.transpose();
  A.diagonal().array() += k.a;
  for (int m = 0; m < 3; ++m) {
    A(kPairI[m], kPairJ[m]) += k.s * sig(m);
    A(kPairJ[m], kPairI[m]) += k.s * sig(m);
  }
  return A;
}

SnhEigensystem StableNeoHookean::eigensystem(const Eigen::Matrix3d& F) const {
  checkFinite(F, "eigensystem");
  const RotationVariantSvd svd = rotationVariantSvd(F);
  const Eigen::Vector3d& sig = svd.sigma;
  const Coefficients k = coefficients(sig.squaredNorm(), sig.prod());
  SnhEigensystem es;
  // Scaling modes: the 3x3 block on vec(U diag(d) V^T), solved small ([Smith18 §4.3]).
  const SymmetricEigen3 eig = symmetricEigen3(scalingBlock(sig, k));
  Eigen::Matrix<double, 9, 3> W;
  for (int m = 0; m < 3; ++m) W.col(m) = outerVec(svd.U, m, svd.V, m);
  es.values.head<3>() = eig.values;
  es.vectors.leftCols<3>() = W * eig.vectors;
  // Twist (antisymmetric) and flip (symmetric) modes of pair (i, j): on (D_ij, D_ji) the Hessian is
  // [[a, -s sigma_k], [-s sigma_k, a]] (same expansion of det), eigenvalues a ± lambda'(J - alpha) sigma_k.
  const double r = std::sqrt(0.5);
  for (int m = 0; m < 3; ++m) {
    const Vector9d wij = outerVec(svd.U, kPairI[m], svd.V, kPairJ[m]);
    const Vector9d wji = outerVec(svd.U, kPairJ[m], svd.V, kPairI[m]);
    es.values(3 + m) = k.a + k.s * sig(m);
    es.vectors.col(3 + m) = r * (wij - wji);
    es.values(6 + m) = k.a - k.s * sig(m);
    es.vectors.col(6 + m) = r * (wij + wji);
  }
  return es;
}

Matrix9d StableNeoHookean::projectedHessian(const Eigen::Matrix3d& F) const {
  checkFinite(F, "projectedHessian");
  return projectedHessian(F, rotationVariantSvd(F));
}

Matrix9d StableNeoHookean::projectedHessian(const Eigen::Matrix3d& F, const RotationVariantSvd& svd) const {
  checkFinite(F, "projectedHessian");
  // H_+ = K D_+ K^T with K = V (x) U (column r + 3c is vec(u_r v_c^T)) and D_+ the clamped Hessian in the
  // singular basis: the scaling block on the diagonal entries D_mm and one 2x2 block per (D_ij, D_ji)
  // pair (twist/flip modes). Built from the eigensystem alone, H_+ is PSD to rounding even where the
  // exact Hessian evaluated from F suffers cancellation (huge, nearly flat elements).
  const Eigen::Vector3d& sig = svd.sigma;
  const Coefficients k = coefficients(sig.squaredNorm(), sig.prod());
  Matrix9d K;
  for (int m = 0; m < 3; ++m)
    for (int c = 0; c < 3; ++c) K.block<3, 3>(3 * m, 3 * c) = svd.V(m, c) * svd.U;
  Matrix9d X;  // K D_+
  // Scaling block ([Smith18 §4.3]): clamp only if Sylvester's criterion says it is not PD.
  Eigen::Matrix3d A = scalingBlock(sig, k);
  const double minor2 = A(0, 0) * A(1, 1) - A(0, 1) * A(0, 1);
  if (!(A(0, 0) > 0.0 && minor2 > 0.0 && A.determinant() > 0.0)) A = psdProjection3(A);
  for (int n = 0; n < 3; ++n) X.col(4 * n) = K.col(0) * A(0, n) + K.col(4) * A(1, n) + K.col(8) * A(2, n);
  // Twist (antisymmetric, a + s sigma_k) and flip (symmetric, a - s sigma_k) modes of pair (i, j): the
  // clamped 2x2 block is [[p, q], [q, p]] with p = (twist+ + flip+) / 2, q = (flip+ - twist+) / 2.
  for (int m = 0; m < 3; ++m) {
    const double twist = std::max(k.a + k.s * sig(m), 0.0);
    const double flip = std::max(k.a - k.s * sig(m), 0.0);
    const double p = 0.5 * (twist + flip);
    const double q = 0.5 * (flip - twist);
    const int ij = kPairI[m] + 3 * kPairJ[m];
    const int ji = kPairJ[m] + 3 * kPairI[m];
    X.col(ij) = p * K.col(ij) + q * K.col(ji);
    X.col(ji) = q * K.col(ij) + p * K.col(ji);
  }
  // H = X K^T column by column (9 axpys of length 9 each; Eigen's generic 9x9 lazy product is slower).
  Matrix9d H;
  for (int b = 0; b < 9; ++b) {
    Vector9d column = K(b, 0) * X.col(0);
    for (int c = 1; c < 9; ++c) column += K(b, c) * X.col(c);
    H.col(b) = column;
  }
  return H;
}

}  // namespace deformation_enrichment::elasticity
