#pragma once
// Transfer calibration: the stamp gain of an example set on another scene, from a few fine solves of that
// scene. The descriptors see geometry only, so a set acquired on another material carries detail of the
// wrong depth (a slab stamp is 3-5x too shallow for the liver, a liver stamp 3x too deep for the slab);
// the material similarity can only fade it. Calibration contacts of the target scene are scored at some
// stamp gain; with a_c = <d, m>_c / |m_c|^2 and s_c = |d_c|^2 / |m_c|^2 (held_out_evaluation.hpp), contact
// c's ratio at a factor g on that gain is sqrt(1 - 2 g a_c + g^2 s_c). Each contact limits the factor:
//   - detail towards its truth (a_c > 0): to its best factor b_c = a_c / s_c. Below b_c part of the gain is
//     kept (at k b_c the ratio is sqrt(1 - (1 - r_c^2)(2k - k^2))), above 2 b_c the contact is worse than
//     coarse, so overshooting costs more than falling short;
//   - detail away from it (a_c <= 0): to the factor at which it is 5 % worse than coarse, the most any
//     contact may lose (solving s_c g^2 - 2 a_c g = 1.05^2 - 1).
// The calibrated factor is the smallest limit, or 0 when no contact's detail points towards its truth.
#include <vector>

#include "deformation_enrichment/acquisition/held_out_evaluation.hpp"

namespace deformation_enrichment::acquisition {

struct TransferCalibration {
  std::vector<double> limits;  ///< the largest factor each calibration contact with detail allows (above)
  double factor = 0.0;         ///< the calibrated factor on the gain the contacts were scored at
};

/// The largest ratio to coarse a calibration contact may reach at the calibrated factor.
inline constexpr double kCalibrationWorstRatio = 1.05;

/// Throws InvalidInputError when no contact of `calibration` received detail (nothing to calibrate on).
TransferCalibration calibrateTransfer(const HeldOutScore& calibration);

}  // namespace deformation_enrichment::acquisition
