#include "deformation_enrichment/descriptors/moment_window.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/hermite/hermite_basis.hpp"
#include "deformation_enrichment/hermite/multi_index.hpp"

namespace deformation_enrichment::descriptors {

Quadrature parseQuadrature(const std::string& name) {
  if (name == "volume") return Quadrature::Volume;
  if (name == "average") return Quadrature::Average;
  throw InvalidInputError("unknown quadrature '" + name + "' (expected volume or average)");
}

std::string toString(Quadrature quadrature) { return quadrature == Quadrature::Volume ? "volume" : "average"; }

Window gatherWindow(const PointSampling& sampling, const Eigen::Vector3d& p, const WindowOptions& options) {
  if (!p.allFinite()) throw InvalidInputError("moment window: evaluation point is not finite");
  if (!(options.scale > 0.0) || !std::isfinite(options.scale))
    throw InvalidInputError("moment window: scale h = " + std::to_string(options.scale) + " must be positive");
  if (!(options.cutoff > 0.0) || !std::isfinite(options.cutoff))
    throw InvalidInputError("moment window: cut-off " + std::to_string(options.cutoff) + " must be positive");
  Window window;
  window.centre = p;
  window.scale = options.scale;
  sampling.pointsWithin(p, options.cutoff * options.scale, window.indices, options.search);
  const Eigen::Index count = static_cast<Eigen::Index>(window.indices.size());
  window.r.resize(3, count);
  window.omega.resize(count);
  window.weight.resize(count);
  const double inverseScale = 1.0 / options.scale;
  for (Eigen::Index k = 0; k < count; ++k) {
    window.r.col(k) = (sampling.points().col(window.indices[k]) - p) * inverseScale;
    window.omega[k] = hermite::gaussianWindow(window.r.col(k).squaredNorm());  // eq. (2)
  }
  if (options.quadrature == Quadrature::Volume) {
    // q_m = V_m / h^3: the volume element of the integral (7) in the scaled variable r.
    const double inverseCube = inverseScale * inverseScale * inverseScale;
    for (Eigen::Index k = 0; k < count; ++k)
      window.weight[k] = window.omega[k] * sampling.volumes()[window.indices[k]] * inverseCube;
  } else {
    // eq. (8): eta_n normalises by sum_m omega_m.
    const double total = window.omega.sum();
    if (total > 0.0) window.weight = window.omega / total;
    else window.weight.setZero();
  }
  return window;
}

namespace {

// sums(c, channel) = sum_m H_c(r_m) weighted(m, channel): the basis of a block of samples is evaluated and
// consumed at once, so it stays in the cache (a window holds thousands of samples).
void accumulateMoments(const Window& window, const Eigen::MatrixXd& weighted, int firstOrder, int lastOrder,
                       Eigen::Map<Eigen::MatrixXd> sums) {
  constexpr Eigen::Index kBlock = 256;
  Eigen::MatrixXd basis;
  for (Eigen::Index start = 0; start < window.r.cols(); start += kBlock) {
    const Eigen::Index length = std::min(kBlock, window.r.cols() - start);
    hermite::evaluateBasis(window.r.middleCols(start, length), firstOrder, lastOrder, basis);
    sums.noalias() += basis.transpose() * weighted.middleRows(start, length);
  }
}

}  // namespace

hermite::MomentList densityMoments(const Window& window, int firstOrder, int lastOrder) {
  hermite::MomentList moments(firstOrder, lastOrder, 1);
  accumulateMoments(window, window.weight, firstOrder, lastOrder,
                    Eigen::Map<Eigen::MatrixXd>(moments.values().data(), moments.channelSize(), 1));  // eq. (8), rho = 1
  return moments;
}

hermite::MomentList fieldMoments(const Window& window, const Eigen::Matrix3Xd& field, int firstOrder,
                                 int lastOrder) {
  if (field.cols() != window.r.cols())
    throw InvalidInputError("fieldMoments: field has " + std::to_string(field.cols()) +
                            " samples, window has " + std::to_string(window.r.cols()));
  if (!field.allFinite()) throw InvalidInputError("fieldMoments: field is not finite");
  hermite::MomentList moments(firstOrder, lastOrder, 3);
  // eq. (11): u_bar (x) H_n, weighted; channel-major values are the columns of a channelSize x 3 matrix.
  const Eigen::MatrixXd weighted = (field.array().rowwise() * window.weight.transpose().array()).transpose();
  accumulateMoments(window, weighted, firstOrder, lastOrder,
                    Eigen::Map<Eigen::MatrixXd>(moments.values().data(), moments.channelSize(), 3));
  return moments;
}

}  // namespace deformation_enrichment::descriptors
