#pragma once
// Hermite moments of a weighted point set around a point p ([Seiler14 eq. 7], 8, 11 and docs/design.md §4):
// r_m = (x_m - p) / h, M_n = sum_m q_m omega(|r_m|) H_n(r_m) f_m with H_n scaled by 1/sqrt(n!), over the
// samples within the cut-off radius. Two quadratures:
//   Volume  (default) q_m = V_m / h^3: a Riemann sum of the integral (7) in r = (x - p)/h, independent of
//           how densely the mesh samples the domain;
//   Average (the paper's eq. 8) q_m = 1 / sum_m omega_m: a weighted mean, biased where the mesh is graded.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "deformation_enrichment/descriptors/point_sampling.hpp"
#include "deformation_enrichment/hermite/moment_list.hpp"

namespace deformation_enrichment::descriptors {

enum class Quadrature { Volume, Average };

/// "volume" or "average"; anything else -> InvalidInputError.
Quadrature parseQuadrature(const std::string& name);
std::string toString(Quadrature quadrature);

struct WindowOptions {
  double scale = 1.0;    ///< window scale h in metres (r = (x - p) / h)
  double cutoff = 4.0;   ///< cut-off radius in units of h (omega(4) / omega(0) = 3.4e-4)
  Quadrature quadrature = Quadrature::Volume;
  NeighbourSearch search = NeighbourSearch::KdTree;
};

/// The samples of one window: their indices into the sampling, scaled offsets r_m, Gaussian weights
/// omega_m and quadrature-weighted omega_m (q_m omega_m).
struct Window {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  double scale = 1.0;
  std::vector<int> indices;
  Eigen::Matrix3Xd r;
  Eigen::VectorXd omega;
  Eigen::VectorXd weight;  ///< q_m omega_m
  bool empty() const { return indices.empty(); }
};

/// Collects the window at p. Throws InvalidInputError for non-finite p, h <= 0 or cutoff <= 0. A window
/// with no sample (contact far from the mesh) is returned empty, not as an error.
Window gatherWindow(const PointSampling& sampling, const Eigen::Vector3d& p, const WindowOptions& options);

/// Moments of the indicator (density rho = 1 on the samples) of orders firstOrder..lastOrder (eq. 7/8).
/// An empty window gives zero moments (no material near p).
hermite::MomentList densityMoments(const Window& window, int firstOrder, int lastOrder);

/// Moments of a vector field sampled at the window's samples (3 x window size), one channel per component
/// (eq. 11). An empty window gives zero moments.
hermite::MomentList fieldMoments(const Window& window, const Eigen::Matrix3Xd& field, int firstOrder,
                                 int lastOrder);

}  // namespace deformation_enrichment::descriptors
