#include "deformation_enrichment/kinematics/mls_deformation_gradient.hpp"

#include <cmath>
#include <limits>
#include <string>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::kinematics {
namespace {

constexpr const char* kWhere = "mlsDeformationGradient: ";

struct Moments {
  double W;  // sum of the normalised weights
  Eigen::Vector3d xBar, yBar;
  Eigen::Matrix3d Apq, Aqq;
};

// Weighted centroids and the shape-matching matrices A_pq, A_qq (Müller et al. 2005, eq. 7).
Moments weightedMoments(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& y, const Eigen::VectorXd& w) {
  if (x.cols() == 0) throw InvalidInputError(std::string(kWhere) + "empty point set");
  if (y.cols() != x.cols() || w.size() != x.cols()) {
    throw InvalidInputError(std::string(kWhere) + "mismatched sizes: " + std::to_string(x.cols()) +
                            " rest points, " + std::to_string(y.cols()) + " deformed points, " +
                            std::to_string(w.size()) + " weights");
  }
  if (!x.allFinite()) throw InvalidInputError(std::string(kWhere) + "rest points contain NaN or Inf");
  if (!y.allFinite()) throw InvalidInputError(std::string(kWhere) + "deformed points contain NaN or Inf");
  if (!w.allFinite()) throw InvalidInputError(std::string(kWhere) + "weights contain NaN or Inf");
  if ((w.array() < 0.0).any()) throw InvalidInputError(std::string(kWhere) + "negative weight");
  const double wMax = w.maxCoeff();
  if (!(wMax > 0.0)) {
    throw InvalidInputError(std::string(kWhere) +
                            "all weights are zero (is the evaluation point far from every sample?)");
  }
  // F and the centroids do not change when all weights are scaled; scaling by the largest keeps sums of
  // huge or subnormal weights finite and non-zero.
  const Eigen::VectorXd wn = w / wMax;
  const double W = wn.sum();
  Moments m;
  m.W = W;
  m.xBar = x * wn / W;
  m.yBar = y * wn / W;
  // Sums of 3 x 3 outer products: fixed-size work per sample, no 3 x n temporaries or matrix-product packing.
  // Local accumulators (registers, not the returned struct).
  Eigen::Matrix3d apq = Eigen::Matrix3d::Zero(), aqq = Eigen::Matrix3d::Zero();
  const Eigen::Vector3d xBar = m.xBar, yBar = m.yBar;
  for (Eigen::Index k = 0; k < x.cols(); ++k) {
    const Eigen::Vector3d q = x.col(k) - xBar;
    const Eigen::Vector3d wq = wn[k] * q;
    apq.noalias() += (y.col(k) - yBar) * wq.transpose();
    aqq.noalias() += q * wq.transpose();
  }
  m.Apq = apq;
  m.Aqq = aqq;
  return m;
}

// F = A_pq A_qq^-1 for symmetric positive definite A_qq: Fᵀ = A_qq^-1 A_pqᵀ.
Eigen::Matrix3d solveShapeMatching(const Eigen::Matrix3d& Apq, const Eigen::Matrix3d& Aqq) {
  const Eigen::Matrix3d Ft = Aqq.ldlt().solve(Apq.transpose());
  if (!Ft.allFinite()) throw NumericalError(std::string(kWhere) + "A_qq solve produced NaN");
  return Ft.transpose();
}

void checkTolerance(const MlsOptions& options) {
  if (!(options.coplanarTolerance > 0.0 && options.coplanarTolerance < 1.0)) {
    throw InvalidInputError(std::string(kWhere) + "coplanarTolerance must lie in (0, 1)");
  }
}

// Coincident samples: the spread is at round-off level of the coordinates themselves.
void checkNotCoincident(double largestEigenvalue, double W, const Eigen::Vector3d& xBar) {
  const double roundOff = 64.0 * std::numeric_limits<double>::epsilon() * xBar.cwiseAbs().maxCoeff();
  if (!(largestEigenvalue > 0.0) || std::sqrt(largestEigenvalue / W) <= roundOff) {
    throw InvalidInputError(std::string(kWhere) + "all weighted samples coincide; F is undefined");
  }
}

// Volume samples: the plain shape-matching fit.
MlsDeformationGradient fitVolume(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& y, const Eigen::VectorXd& w,
                                 const MlsOptions& options) {
  checkTolerance(options);
  const Moments m = weightedMoments(x, y, w);
  const Eigen::Vector3d lambda = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(m.Aqq).eigenvalues();  // ascending
  checkNotCoincident(lambda[2], m.W, m.xBar);
  const double tol = options.coplanarTolerance;
  if (lambda[1] < tol * lambda[2]) {
    throw InvalidInputError(std::string(kWhere) + "weighted samples are collinear; F is undefined");
  }
  if (lambda[0] < tol * lambda[2]) {
    throw InvalidInputError(std::string(kWhere) +
                            "weighted samples are coplanar; pass the rest and deformed surface normals");
  }
  MlsDeformationGradient result;
  result.xBar = m.xBar;
  result.yBar = m.yBar;
  result.F = solveShapeMatching(m.Apq, m.Aqq);  // F = A_pq A_qq^-1 ([Seiler14 §4.3], [Mueller05])
  result.normalCompleted = false;
  return result;
}

// Surface samples: tangential columns from the samples, normal column from the normals.
MlsDeformationGradient fitSurface(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& y, const Eigen::VectorXd& w,
                                  const Eigen::Vector3d& restNormal, const Eigen::Vector3d& deformedNormal,
                                  const MlsOptions& options) {
  checkTolerance(options);
  if (!restNormal.allFinite() || !deformedNormal.allFinite()) {
    throw InvalidInputError(std::string(kWhere) + "surface normal contains NaN or Inf");
  }
  if (!(restNormal.norm() > 0.0) || !(deformedNormal.norm() > 0.0)) {
    throw InvalidInputError(std::string(kWhere) + "surface normal is the zero vector");
  }
  const Moments m = weightedMoments(x, y, w);
  checkNotCoincident(Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(m.Aqq).eigenvalues()[2], m.W, m.xBar);
  const Eigen::Vector3d nx = restNormal.normalized();
  const Eigen::Vector3d ny = deformedNormal.normalized();

  // Project rest offsets on the rest tangent plane and deformed offsets on the deformed one:
  // q_t = T Tᵀ q, p_t = (I - n_y n_yᵀ) p. Then A_{p_t q_t} = P_y A_pq T Tᵀ and A_{q_t q_t} = T (Tᵀ A_qq T) Tᵀ.
  Eigen::Matrix<double, 3, 2> T;  // orthonormal rest tangent basis
  T.col(0) = nx.unitOrthogonal();
  T.col(1) = nx.cross(T.col(0));
  const Eigen::Matrix2d Mtt = T.transpose() * m.Aqq * T;
  const Eigen::Vector2d mu = Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(Mtt).eigenvalues();  // ascending
  if (!(mu[0] >= options.coplanarTolerance * mu[1]) || !(mu[1] > 0.0)) {
    throw InvalidInputError(std::string(kWhere) +
                            "weighted samples projected on the rest tangent plane are collinear "
                            "(collinear samples, or a rest normal lying in the sample plane)");
  }
  const Eigen::Matrix3d Py = Eigen::Matrix3d::Identity() - ny * ny.transpose();
  const Eigen::Matrix<double, 3, 2> Apt = Py * m.Apq * T;
  // Tangential part G = A_{p_t q_t} A_{q_t q_t}^+ = Apt Mtt^-1 Tᵀ (shape matching restricted to the plane).
  const Eigen::Matrix<double, 3, 2> GT = Mtt.ldlt().solve(Apt.transpose()).transpose();
  if (!GT.allFinite()) throw NumericalError(std::string(kWhere) + "tangential solve produced NaN");
  const double areaRatio = GT.col(0).cross(GT.col(1)).norm();

  double stretch = 1.0;
  switch (options.normalStretch) {
    case NormalStretch::DeformationTransfer:
      stretch = std::sqrt(areaRatio);  // fourth vertex e1 x e2 / sqrt|e1 x e2| scales like sqrt(area)
      break;
    case NormalStretch::Unit:
      stretch = 1.0;
      break;
    case NormalStretch::VolumePreserving:
      if (!(areaRatio > 1e-12)) {
        throw NumericalError(std::string(kWhere) +
                             "deformed patch has collapsed; a volume-preserving normal stretch is undefined");
      }
      stretch = 1.0 / areaRatio;
      break;
  }

  MlsDeformationGradient result;
  result.xBar = m.xBar;
  result.yBar = m.yBar;
  result.F = GT * T.transpose() + stretch * ny * nx.transpose();  // F = G + lambda n_y n_xᵀ
  result.normalCompleted = true;
  return result;
}

}  // namespace

MlsDeformationGradient mlsDeformationGradient(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& y,
                                              const Eigen::VectorXd& w, const MlsOptions& options) {
  return fitVolume(x, y, w, options);
}

MlsDeformationGradient mlsDeformationGradient(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& y,
                                              const Eigen::VectorXd& w, const Eigen::Vector3d& restNormal,
                                              const Eigen::Vector3d& deformedNormal,
                                              const MlsOptions& options) {
  return fitSurface(x, y, w, restNormal, deformedNormal, options);
}

}  // namespace deformation_enrichment::kinematics
