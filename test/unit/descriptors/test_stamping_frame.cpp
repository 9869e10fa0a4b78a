// Continuity of the stamping frame B (docs/design.md §8): b_x must not jump where a rule's direction crosses its
// tolerance, and with the previous frame's b_x a stream keeps its orientation where the rules have none.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <cmath>

#include "deformation_enrichment/descriptors/stamping_frame.hpp"

using namespace deformation_enrichment;
using descriptors::FrameRule;
using descriptors::stampingFrame;

namespace {

// rho with rho_0 = 1 and rho_1 = (tx, ty, -1): a site whose tangential moment is (tx, ty).
hermite::MomentList site(double tx, double ty) {
  hermite::MomentList rho(0, 1);
  rho.order(0)[0] = 1.0;
  rho.order(1) = Eigen::Vector3d(tx, ty, -1.0);
  return rho;
}

// mu whose only order-1 moment is the shear G(0, 2) = s (u_x grows with z): shear direction +x for s > 0.
hermite::MomentList shear(double s) {
  hermite::MomentList mu(1, 1, 3);
  mu.order(1, 0) = Eigen::Vector3d(0.0, 0.0, s);
  mu.order(1, 2) = Eigen::Vector3d(0.0, 0.0, 1.0);  // a press, so |mu| does not vanish with the shear
  return mu;
}

}  // namespace

TEST(StampingFrame, BxTurnsContinuouslyAsTheSiteTangentCrossesItsTolerance) {
  // rho_1 tangential along y grows through [0.5, 3] tolerances while the shear points along x: the frame
  // turns from the shear's x to the site's y without a step.
  const double tolerance = 1e-3, scale = 1.0 + std::sqrt(1.0 + 0.0);  // |rho_0| + |rho_1| (tangent tiny)
  const hermite::MomentList mu = shear(0.5);
  Eigen::Vector3d previous = stampingFrame(Eigen::Vector3d::UnitZ(), site(0, 0.5 * tolerance * scale), &mu, tolerance).B.col(0);
  EXPECT_GT(previous.x(), 0.999);
  double largestStep = 0.0;
  for (int k = 1; k <= 500; ++k) {
    const double t = (0.5 + 2.5 * k / 500.0) * tolerance * scale;
    const Eigen::Vector3d bx = stampingFrame(Eigen::Vector3d::UnitZ(), site(0, t), &mu, tolerance).B.col(0);
    largestStep = std::max(largestStep, (bx - previous).norm());
    previous = bx;
  }
  EXPECT_GT(previous.y(), 0.999) << "the site rule decides from two tolerances on";
  EXPECT_LT(largestStep, 0.02) << "no jump of b_x (a step rule turns it by 90 degrees at once)";
}

TEST(StampingFrame, PreviousAxisKeepsTheShearSignAndTheFallback) {
  const Eigen::Vector3d n = Eigen::Vector3d::UnitZ();
  const hermite::MomentList flat = site(0, 0), pushed = shear(-0.3);
  // Without history the shear's sign decides (as examples are described): b_x = -x.
  EXPECT_LT(stampingFrame(n, flat, &pushed).B.col(0).x(), -0.999);
  // With a previous b_x of +x the sign follows it.
  const Eigen::Vector3d plusX = Eigen::Vector3d::UnitX();
  const auto kept = stampingFrame(n, flat, &pushed, 1e-3, &plusX);
  EXPECT_GT(kept.B.col(0).x(), 0.999);
  EXPECT_EQ(kept.rule, FrameRule::DeformationDirection);
  // No site or shear direction: the fixed choice is the previous b_x, projected on the tangent plane.
  const Eigen::Vector3d tilted = Eigen::Vector3d(1.0, 1.0, 0.5).normalized();
  const auto fallback = stampingFrame(n, flat, nullptr, 1e-3, &tilted);
  EXPECT_EQ(fallback.rule, FrameRule::Fixed);
  EXPECT_LT((fallback.B.col(0) - Eigen::Vector3d(1, 1, 0).normalized()).norm(), 1e-12);
  EXPECT_NEAR(fallback.B.determinant(), 1.0, 1e-12);
  // A previous axis along the normal carries no direction: the world-axis rule.
  const auto alongNormal = stampingFrame(n, flat, nullptr, 1e-3, &n);
  EXPECT_GT(alongNormal.B.col(0).x(), 0.999);
}
