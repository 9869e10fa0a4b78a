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
  const double W = w.sum();
  if (!(W > 0.0)) {
    throw InvalidInputError(std::string(kWhere) +
                            "all weights are zero (is the evaluation point far from every sample?)");
  }
  Moments m;
  m.xBar = x * w / W;
  m.yBar = y * w / W;
  const Eigen::Matrix3Xd q = x.colwise() - m.xBar;
  const Eigen::Matrix3Xd p = y.colwise() - m.yBar;
  m.Apq = p * w.asDiagonal() * q.transpose();
  m.Aqq = q * w.asDiagonal() * q.transpose();
  return m;
}

// F = A_pq A_qq^-1 for symmetric positive definite A_qq: Fᵀ = A_qq^-1 A_pqᵀ.
Eigen::Matrix3d solveShapeMatching(const Eigen::Matrix3d& Apq, const Eigen::Matrix3d& Aqq) {
  const Eigen::Matrix3d Ft = Aqq.ldlt().solve(Apq.transpose());
  if (!Ft.allFinite()) throw NumericalError(std::string(kWhere) + "A_qq solve produced NaN");
  return Ft.transpose();
}

MlsDeformationGradient fit(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& y, const Eigen::VectorXd& w,
                           const Eigen::Vector3d* restNormal, const Eigen::Vector3d* deformedNormal,
                           const MlsOptions& options) {
  if (!(options.coplanarTolerance > 0.0 && options.coplanarTolerance < 1.0)) {
    throw InvalidInputError(std::string(kWhere) + "coplanarTolerance must lie in (0, 1)");
  }
  const Moments m = weightedMoments(x, y, w);
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(m.Aqq);
  const Eigen::Vector3d lambda = eig.eigenvalues();  // ascending
  const double W = w.sum();
  // Coincident samples: the spread is at round-off level of the coordinates themselves.
  const double roundOff = 64.0 * std::numeric_limits<double>::epsilon() * m.xBar.cwiseAbs().maxCoeff();
  if (!(lambda[2] > 0.0) || std::sqrt(lambda[2] / W) <= roundOff) {
    throw InvalidInputError(std::string(kWhere) + "all weighted samples coincide; F is undefined");
  }
  const double tol = options.coplanarTolerance;
  if (lambda[1] < tol * lambda[2]) {
    throw InvalidInputError(std::string(kWhere) + "weighted samples are collinear; F is undefined");
  }

  MlsDeformationGradient result;
  result.xBar = m.xBar;
  result.yBar = m.yBar;
  if (lambda[0] >= tol * lambda[2]) {
    result.F = solveShapeMatching(m.Apq, m.Aqq);  // eq. F = A_pq A_qq^-1 (paper 000 §4.3, [MHTG05])
    result.normalCompleted = false;
    return result;
  }

  // Coplanar samples: complete the fit in the normal direction.
  if (restNormal == nullptr || deformedNormal == nullptr) {
    throw InvalidInputError(std::string(kWhere) +
                            "weighted samples are coplanar; pass the rest and deformed surface normals");
  }
  if (!restNormal->allFinite() || !deformedNormal->allFinite()) {
    throw InvalidInputError(std::string(kWhere) + "surface normal contains NaN or Inf");
  }
  if (!(restNormal->norm() > 0.0) || !(deformedNormal->norm() > 0.0)) {
    throw InvalidInputError(std::string(kWhere) + "surface normal is the zero vector");
  }
  const Eigen::Vector3d nx = restNormal->normalized();
  const Eigen::Vector3d ny = deformedNormal->normalized();
  const Eigen::Vector3d planeNormal = eig.eigenvectors().col(0);
  if (std::abs(nx.dot(planeNormal)) < 0.1) {
    throw InvalidInputError(std::string(kWhere) +
                            "rest normal lies (almost) in the plane of the coplanar samples");
  }

  // In-plane map from the pseudo-inverse of A_qq on the sample plane, to measure the area ratio.
  const Eigen::Vector3d t1 = eig.eigenvectors().col(1), t2 = eig.eigenvectors().col(2);
  const Eigen::Matrix3d AqqPinv = t1 * t1.transpose() / lambda[1] + t2 * t2.transpose() / lambda[2];
  const Eigen::Matrix3d Fplane = m.Apq * AqqPinv;
  const double areaRatio = (Fplane * t1).cross(Fplane * t2).norm();

  double stretch = 1.0;
  switch (options.normalStretch) {
    case NormalStretch::DeformationTransfer:
      stretch = std::sqrt(areaRatio);  // |e1 x e2| / sqrt|e1 x e2| scales like sqrt(area)
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

  // Virtual sample (q, p) = (n_x, stretch n_y) with weight s of the in-plane spread's size, so the
  // completed A_qq is well conditioned. For exactly coplanar samples the result does not depend on s.
  const double s = lambda[1] + lambda[2];
  const Eigen::Matrix3d Aqq = m.Aqq + s * nx * nx.transpose();
  const Eigen::Matrix3d Apq = m.Apq + s * stretch * ny * nx.transpose();
  result.F = solveShapeMatching(Apq, Aqq);
  result.normalCompleted = true;
  return result;
}

}  // namespace

MlsDeformationGradient mlsDeformationGradient(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& y,
                                              const Eigen::VectorXd& w, const MlsOptions& options) {
  return fit(x, y, w, nullptr, nullptr, options);
}

MlsDeformationGradient mlsDeformationGradient(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& y,
                                              const Eigen::VectorXd& w, const Eigen::Vector3d& restNormal,
                                              const Eigen::Vector3d& deformedNormal,
                                              const MlsOptions& options) {
  return fit(x, y, w, &restNormal, &deformedNormal, options);
}

}  // namespace deformation_enrichment::kinematics
