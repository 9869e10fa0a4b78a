#include "deformation_enrichment/acquisition/transfer_calibration.hpp"

#include <algorithm>
#include <cmath>

#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::acquisition {

TransferCalibration calibrateTransfer(const HeldOutScore& calibration) {
  constexpr double kLoss = kCalibrationWorstRatio * kCalibrationWorstRatio - 1.0;
  TransferCalibration out;
  bool towardsTruth = false;
  for (const ContactScore& c : calibration.contacts) {
    if (!(c.detailSize > 0.0)) continue;
    const double a = c.detailAlong, s = c.detailSize;
    towardsTruth = towardsTruth || a > 0.0;
    // The positive root of s g^2 - 2 a g - kLoss = 0, written without cancellation for a <= 0.
    out.limits.push_back(a > 0.0 ? a / s : kLoss / (-a + std::sqrt(a * a + s * kLoss)));
  }
  if (out.limits.empty())
    throw InvalidInputError("transfer calibration: no calibration contact received detail from the example set");
  out.factor = towardsTruth ? *std::min_element(out.limits.begin(), out.limits.end()) : 0.0;
  return out;
}

}  // namespace deformation_enrichment::acquisition
