#include <gtest/gtest.h>

#include "deformation_enrichment/acquisition/transfer_calibration.hpp"
#include "deformation_enrichment/error.hpp"

using namespace deformation_enrichment;

namespace {

// A contact whose detail d, against the missing displacement m, has <d, m> / |m|^2 = along and
// |d|^2 / |m|^2 = size (along^2 <= size: Cauchy-Schwarz).
acquisition::ContactScore contact(double along, double size) {
  acquisition::ContactScore c;
  c.coarseRms = 1.0;
  c.detailAlong = along;
  c.detailSize = size;
  return c;
}

}  // namespace

TEST(TransferCalibration, TakesTheSmallestBestFactorSoNoCalibrationContactOvershoots) {
  // Best factors 4, 1.5 and 8 (e.g. a slab set on the softer liver: detail 2-8x too shallow).
  acquisition::HeldOutScore score;
  score.contacts = {contact(0.16, 0.04), contact(0.015, 0.01), contact(0.08, 0.01), contact(0.0, 0.0)};
  const acquisition::TransferCalibration calibration = acquisition::calibrateTransfer(score);
  ASSERT_EQ(calibration.limits.size(), 3u);  // the contact without detail tells nothing
  EXPECT_DOUBLE_EQ(calibration.factor, 1.5);
  // Every calibration contact gains at the calibrated factor; the pooled least-squares factor (sum along /
  // sum size = 4.25) would leave the contact of best factor 1.5 worse than coarse.
  for (int i = 0; i < 3; ++i) EXPECT_LT(score.contacts[i].ratioAtGain(calibration.factor), 1.0);
  EXPECT_NEAR(score.bestGain(), 4.25, 1e-12);
  EXPECT_GT(score.contacts[1].ratioAtGain(score.bestGain()), 1.0);
}

TEST(TransferCalibration, DetailAwayFromTheTruthLimitsTheFactorToFivePercentWorseThanCoarse) {
  acquisition::HeldOutScore score;
  score.contacts = {contact(0.16, 0.04), contact(-0.01, 0.02)};
  const acquisition::TransferCalibration calibration = acquisition::calibrateTransfer(score);
  ASSERT_EQ(calibration.limits.size(), 2u);
  EXPECT_DOUBLE_EQ(calibration.limits[0], 4.0);
  EXPECT_LT(calibration.factor, 4.0);
  EXPECT_DOUBLE_EQ(calibration.factor, calibration.limits[1]);
  EXPECT_NEAR(score.contacts[1].ratioAtGain(calibration.factor), acquisition::kCalibrationWorstRatio, 1e-12);
  // Where that allows more than every best factor, the best factors decide.
  score.contacts[1] = contact(-1e-4, 1e-4);
  EXPECT_DOUBLE_EQ(acquisition::calibrateTransfer(score).factor, 4.0);
  // No contact's detail points towards its truth: no transfer.
  score.contacts[0] = contact(-0.01, 0.04);
  EXPECT_EQ(acquisition::calibrateTransfer(score).factor, 0.0);
}

TEST(TransferCalibration, RefusesContactsWithoutDetail) {
  acquisition::HeldOutScore score;
  EXPECT_THROW(acquisition::calibrateTransfer(score), InvalidInputError);
  score.contacts = {contact(0.0, 0.0)};
  EXPECT_THROW(acquisition::calibrateTransfer(score), InvalidInputError);
}
