#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/hermite/hermite_basis.hpp"
#include "deformation_enrichment/hermite/moment_list.hpp"
#include "deformation_enrichment/hermite/multi_index.hpp"
#include "deformation_enrichment/hermite/symmetric_tensor.hpp"

using namespace deformation_enrichment;
using namespace deformation_enrichment::hermite;

namespace {
Eigen::Matrix3d randomRotation(std::mt19937& rng) {
  std::normal_distribution<double> normal;
  Eigen::Quaterniond q(normal(rng), normal(rng), normal(rng), normal(rng));
  return q.normalized().toRotationMatrix();
}

// Appendix B written out over full tensors, one loop per index, as an independent reference.
Eigen::VectorXd transformFullOrder3(const Eigen::VectorXd& full, const Eigen::Matrix3d& T) {
  Eigen::VectorXd out = Eigen::VectorXd::Zero(27);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k)
        for (int a = 0; a < 3; ++a)
          for (int b = 0; b < 3; ++b)
            for (int c = 0; c < 3; ++c) out[9 * i + 3 * j + k] += full[9 * a + 3 * b + c] * T(i, a) * T(j, b) * T(k, c);
  return out;
}
}  // namespace

TEST(TensorRotation, MatchesExplicitFullTensorFormula) {
  std::mt19937 rng(3);
  std::normal_distribution<double> normal;
  Eigen::Matrix3d T;  // any linear map, not only rotations
  for (int k = 0; k < 9; ++k) T(k) = normal(rng);
  Eigen::VectorXd distinct(10);
  for (int k = 0; k < 10; ++k) distinct[k] = normal(rng);
  const Eigen::VectorXd expected = transformFullOrder3(toFullTensor(3, distinct), T);
  const Eigen::VectorXd ours = toFullTensor(3, transformTensor(3, distinct, T));
  EXPECT_LT((ours - expected).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_EQ(fromFullTensor(3, toFullTensor(3, distinct)), distinct);
  // Order 2 is the matrix congruence T G T^T.
  Eigen::VectorXd g2(6);
  g2 << 1, 2, 3, 4, 5, 6;
  Eigen::Matrix3d G;
  G << 1, 2, 3, 2, 4, 5, 3, 5, 6;
  const Eigen::Matrix3d expected2 = T * G * T.transpose();
  const Eigen::VectorXd ours2 = transformTensor(2, g2, T);
  EXPECT_NEAR(ours2[1], expected2(0, 1), 1e-12);
  EXPECT_NEAR(ours2[4], expected2(1, 2), 1e-12);
  EXPECT_NEAR(ours2[5], expected2(2, 2), 1e-12);
  EXPECT_THROW(symmetricTransform(2, Eigen::Matrix3d::Constant(NAN)), InvalidInputError);
}

TEST(TensorRotation, MomentsOfRotatedPointsEqualRotatedMoments) {
  // Appendix B: rotating the moment tensors gives the moments of the rotated point set, for the scalar
  // (rho) and the vector-valued (mu, where the field rotates too) case.
  std::mt19937 rng(5);
  std::normal_distribution<double> normal;
  const int count = 50;
  Eigen::Matrix3Xd points(3, count), field(3, count);
  Eigen::VectorXd weights(count);
  for (int m = 0; m < count; ++m) {
    points.col(m) = Eigen::Vector3d(normal(rng), normal(rng), normal(rng));
    field.col(m) = Eigen::Vector3d(normal(rng), normal(rng), normal(rng));
    weights[m] = 0.5 + std::abs(normal(rng));
  }
  const Eigen::Matrix3d Q = randomRotation(rng);
  auto moments = [&](const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& u) {
    MomentList scalar(0, 4, 1), vector(1, 3, 3);
    for (int m = 0; m < count; ++m) {
      const double w = weights[m] * gaussianWindow(x.col(m).squaredNorm());
      scalar.values() += w * evaluateBasis(x.col(m), 0, 4);
      const Eigen::VectorXd h = evaluateBasis(x.col(m), 1, 3);
      for (int c = 0; c < 3; ++c) vector.values().segment(c * h.size(), h.size()) += w * u(c, m) * h;
    }
    return std::make_pair(scalar, vector);
  };
  const auto original = moments(points, field);
  const auto rotated = moments(Q * points, Q * field);
  EXPECT_LT((original.first.transformed(Q).values() - rotated.first.values()).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((original.second.transformed(Q).values() - rotated.second.values()).cwiseAbs().maxCoeff(), 1e-12);
  // Inner products and norms are rotation invariant.
  EXPECT_NEAR(norm(original.first), norm(rotated.first), 1e-12);
  EXPECT_NEAR(inner(original.second, original.second.transformed(Q)),
              inner(rotated.second, rotated.second.transformed(Q)), 1e-11);
  // Composition: T(Q1 Q2) = T(Q1) T(Q2).
  const Eigen::Matrix3d Q2 = randomRotation(rng);
  EXPECT_LT((original.first.transformed(Q * Q2).values() - original.first.transformed(Q2).transformed(Q).values())
                .cwiseAbs()
                .maxCoeff(),
            1e-12);
}
