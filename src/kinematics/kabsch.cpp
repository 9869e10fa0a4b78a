#include "deformation_enrichment/kinematics/kabsch.hpp"

#include <limits>
#include <string>

#include <Eigen/SVD>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/kinematics/polar_decomposition.hpp"

namespace deformation_enrichment::kinematics {
namespace {

void checkPoints(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& y, Eigen::Index weights) {
  if (x.cols() == 0) throw InvalidInputError("kabsch: empty point set");
  if (y.cols() != x.cols() || weights != x.cols()) {
    throw InvalidInputError("kabsch: mismatched sizes: " + std::to_string(x.cols()) + " points x, " +
                            std::to_string(y.cols()) + " points y, " + std::to_string(weights) + " weights");
  }
  if (!x.allFinite() || !y.allFinite()) throw InvalidInputError("kabsch: points contain NaN or Inf");
}

// The fit for weights weight(m) (>= 0, not all zero). Centroids, then the cross-covariance
// A = sum w_m (y_m - y_bar)(x_m - x_bar)^T about them (centred: no cancellation for points far from the
// origin), each in one pass of scalar sums: 3 x 3 outer products per point, or a 3 x n by n x 3 product,
// took 2.5-3x the instructions on 15k points.
template <class Weight>
RigidTransform fit(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& y, const Weight& weight) {
  double total = 0.0;
  Eigen::Vector3d xSum = Eigen::Vector3d::Zero(), ySum = Eigen::Vector3d::Zero();
  for (Eigen::Index m = 0; m < x.cols(); ++m) {
    const double w = weight(m);
    total += w;
    xSum += w * x.col(m);
    ySum += w * y.col(m);
  }
  const Eigen::Vector3d xBar = xSum / total, yBar = ySum / total;
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
  for (Eigen::Index m = 0; m < x.cols(); ++m) {
    const Eigen::Vector3d dx = x.col(m) - xBar, dy = weight(m) * (y.col(m) - yBar);
    for (int c = 0; c < 3; ++c) A.col(c) += dx[c] * dy;
  }
  // The optimal rotation is the proper rotation factor of the polar decomposition A = R S (the SVD with the
  // reflection fix).
  RigidTransform result;
  result.R = polarDecomposition(A).R;
  result.t = yBar - result.R * xBar;
  // Rank <= 1: the rotation about the common line is free. Judge the second singular value against
  // the first at round-off level.
  const Eigen::Vector3d sigma = Eigen::JacobiSVD<Eigen::Matrix3d>(A).singularValues();
  result.unique = sigma[1] > 1e3 * std::numeric_limits<double>::epsilon() * sigma[0];
  return result;
}

}  // namespace

RigidTransform kabsch(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& y, const Eigen::VectorXd& w) {
  checkPoints(x, y, w.size());
  if (!w.allFinite()) throw InvalidInputError("kabsch: weights contain NaN or Inf");
  if ((w.array() < 0.0).any()) throw InvalidInputError("kabsch: negative weight");
  const double wMax = w.maxCoeff();
  if (!(wMax > 0.0)) throw InvalidInputError("kabsch: all weights are zero");
  const double scale = 1.0 / wMax;  // scale-free; keeps sums of huge or subnormal weights finite
  return fit(x, y, [&](Eigen::Index m) { return w[m] * scale; });
}

RigidTransform kabsch(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& y) {
  checkPoints(x, y, x.cols());
  return fit(x, y, [](Eigen::Index) { return 1.0; });
}

}  // namespace deformation_enrichment::kinematics
