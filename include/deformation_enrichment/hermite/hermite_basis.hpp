#pragma once
// Multivariate probabilists' Hermite basis of [Seiler14 eq. 2-3]: with the Gaussian window
// omega(r) = (2 pi)^(-3/2) exp(-|r|^2 / 2), (-1)^n grad^n omega = He_alpha(r) omega, and the basis
// components are H_alpha(r) = He_ax(r_x) He_ay(r_y) He_az(r_z) / sqrt(n!).
#include <Eigen/Core>

namespace deformation_enrichment::hermite {

/// Gaussian window omega of eq. (2) evaluated from the squared radius |r|^2.
double gaussianWindow(double squaredRadius);

/// Univariate probabilists' Hermite polynomial He_k(x) (He_0 = 1, He_1 = x, He_{k+1} = x He_k - k He_{k-1}).
double hermiteHe(int k, double x);

/// Index of the first component of order n in a list that starts at order 0: sum_{k<n} (k+1)(k+2)/2.
constexpr int orderOffset(int order) { return order * (order + 1) * (order + 2) / 6; }

/// Total number of components of orders firstOrder..lastOrder.
int basisSize(int firstOrder, int lastOrder);

/// H_alpha(r_m) of every sample m (a column of r) for all distinct components of orders firstOrder..lastOrder
/// (eq. 3, scaled by 1/sqrt(n!)): row m of `out` (r.cols() x basisSize(first, last)) holds sample m's values
/// order by order in multiIndices() order. Throws InvalidInputError for orders outside
/// [0, kMaxHermiteOrder] or first > last.
void evaluateBasis(const Eigen::Ref<const Eigen::Matrix3Xd>& r, int firstOrder, int lastOrder, Eigen::MatrixXd& out);

/// The values at one point.
Eigen::VectorXd evaluateBasis(const Eigen::Vector3d& r, int firstOrder, int lastOrder);

}  // namespace deformation_enrichment::hermite
