#include <gtest/gtest.h>

#include <limits>

#include <Eigen/Geometry>
#include <Eigen/LU>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/kinematics/kabsch.hpp"
#include "random_rotation.hpp"

using namespace deformation_enrichment;
using kinematics::kabsch;

// Seed 003's use: the 3D rotation between a rest and a deformed triangle. A rigidly moved triangle
// gives back the motion exactly; three points are enough (rank 2 cross-covariance).
TEST(Kabsch, RecoversRigidMotionOfATriangle) {
  Eigen::Matrix3Xd triangle(3, 3);
  triangle << 0.759919, 0.767822, 0.726977,  //
      -0.015194, -0.0212492, -0.00749985,    //
      6.38401, 6.3669, 6.38692;
  const Eigen::Matrix3d Q = randomRotation(51);
  const Eigen::Vector3d shift(0.1, -0.2, 0.3);
  const auto rt = kabsch(triangle, (Q * triangle).colwise() + shift);
  EXPECT_TRUE(rt.unique);
  EXPECT_LT((rt.R - Q).norm(), 1e-10);
  EXPECT_LT((rt.R * triangle + rt.t.replicate(1, 3) - ((Q * triangle).colwise() + shift)).norm(), 1e-12);
}

// A mirrored cloud: the unconstrained orthogonal fit would be the mirror; the fix returns a proper
// rotation that is still the best among rotations (no other rotation tried does better).
TEST(Kabsch, ReflectionFixGivesBestProperRotation) {
  std::srand(52);
  const Eigen::Matrix3Xd x = Eigen::Vector3d(1.0, 0.5, 0.2).asDiagonal() * Eigen::Matrix3Xd::Random(3, 30);
  const Eigen::Matrix3Xd y = randomRotation(53) * Eigen::Vector3d(1, -1, 1).asDiagonal() * x;
  const auto rt = kabsch(x, y);
  EXPECT_NEAR(rt.R.determinant(), 1.0, 1e-12);
  const Eigen::Vector3d xBar = x.rowwise().mean(), yBar = y.rowwise().mean();
  auto cost = [&](const Eigen::Matrix3d& R) {  // with the optimal translation for R
    return ((R * x).colwise() + (yBar - R * xBar) - y).squaredNorm();
  };
  const double best = cost(rt.R);
  EXPECT_LT((rt.t - (yBar - rt.R * xBar)).norm(), 1e-14);
  for (int k = 0; k < 200; ++k) {
    const Eigen::Matrix3d perturbed =
        Eigen::AngleAxisd(0.05, Eigen::Vector3d::Random().normalized()).toRotationMatrix() * rt.R;
    EXPECT_GT(cost(perturbed), best);
  }
}

TEST(Kabsch, CollinearPointsGiveAProperButNonUniqueRotation) {
  Eigen::Matrix3Xd line(3, 4);
  for (int m = 0; m < 4; ++m) line.col(m) = Eigen::Vector3d(1, 2, -1) * m;
  const Eigen::Matrix3d Q = randomRotation(54);
  const auto rt = kabsch(line, Q * line);
  EXPECT_FALSE(rt.unique);
  EXPECT_TRUE(rt.R.allFinite());
  EXPECT_NEAR(rt.R.determinant(), 1.0, 1e-12);
  EXPECT_LT((rt.R * line + rt.t.replicate(1, 4) - Q * line).norm(), 1e-12);  // still a minimiser
}

TEST(Kabsch, BadInputThrows) {
  std::srand(55);
  const Eigen::Matrix3Xd x = Eigen::Matrix3Xd::Random(3, 5);
  EXPECT_THROW(kabsch(Eigen::Matrix3Xd(3, 0), Eigen::Matrix3Xd(3, 0)), InvalidInputError);
  EXPECT_THROW(kabsch(x, x.leftCols(4)), InvalidInputError);
  EXPECT_THROW(kabsch(x, x, Eigen::VectorXd::Ones(4)), InvalidInputError);
  EXPECT_THROW(kabsch(x, x, Eigen::VectorXd::Zero(5)), InvalidInputError);
  EXPECT_THROW(kabsch(x, x, -Eigen::VectorXd::Ones(5)), InvalidInputError);
  Eigen::Matrix3Xd nan = x;
  nan(2, 1) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(kabsch(nan, x), InvalidInputError);
  EXPECT_THROW(kabsch(x, nan), InvalidInputError);
}
