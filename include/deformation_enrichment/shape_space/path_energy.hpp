#pragma once
// The discrete path energy ([Brandt16 eq. 4]) E[x_0..x_m] = sum_k W(x_k, x_k+1) + W(x_k+1, x_k) over the
// segments of an open path (a closed one also has the segment x_m -> x_0), its gradient per shape (the
// left-hand side of eq. 3), the path length and the flow tangents of eq. 9: one implementation for the
// flow, the geodesic solvers and the tools.
//
// The segment terms come from DeformationEnergy::pathSegments: shapes and segments are evaluated in parallel
// (OpenMP) on meshes of >= 1000 vertices (each energy pass then runs serially; on small meshes the team's idle
// spinning costs more than the work on a loaded machine), so the energy must be safe to call from several
// threads (DiscreteShells is). Errors of the energy (wrong sizes, non-finite or degenerate shapes:
// InvalidInputError) are passed on.
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "deformation_enrichment/shape_space/deformation_energy.hpp"

namespace deformation_enrichment::shape_space {

/// Eq. 4; with `gradients`, d(eq. 4)/dx_k for every shape k (the ends of an open path included unless
/// !endGradients: zero vectors there, for solvers that hold the ends fixed).
double pathEnergy(const DeformationEnergy& energy, const std::vector<Eigen::VectorXd>& shapes, bool closed = false,
                  std::vector<Eigen::VectorXd>* gradients = nullptr, bool endGradients = true);

/// sum_k sqrt((W(x_k, x_k+1) + W(x_k+1, x_k)) / 2) over the segments (W approximates the squared
/// Riemannian distance to second order, [Brandt16 §5]).
double pathLength(const DeformationEnergy& energy, const std::vector<Eigen::VectorXd>& shapes, bool closed = false);

/// The rest Hessians d2d2 W(x_k, x_k) of the shapes (both triangles stored; in parallel on meshes of >= 1000
/// vertices): half eq. 9's metric, and the reduced geodesic solver's start model, so a caller with both at one
/// path computes them once. Without `ends`, the first and last are left empty (an open path's fixed ends).
/// Written into `hessians` (resized to the shapes) in place: a caller that keeps it reuses the storage
/// (measured: fresh 3 MB matrices' page faults cost more than their assembly on the finger).
void restHessians(const DeformationEnergy& energy, const std::vector<Eigen::VectorXd>& shapes,
                  std::vector<Eigen::SparseMatrix<double>>& hessians, bool ends = true);

/// Flow tangents of eq. 9 at every shape: v_k = -1/2 H_k^-1 d(eq. 4)/dx_k with H_k = d1d1 W(x_k, x_k) +
/// d2d2 W(x_k, x_k) = 2 d2d2 W(x_k, x_k) plus a small ridge (rigid null space); zero vectors at the fixed
/// ends of an open path. Used to enrich the subspaces of short sequences and of geodesics ([Brandt16 §6]).
/// Measured on a small geodesic: one metric shared by all shapes (the middle one's) left the reduced length
/// 0.26 % off the full one after a round of enrichment, the per-shape metric 0.005 %.
std::vector<Eigen::VectorXd> flowTangents(const DeformationEnergy& energy, const std::vector<Eigen::VectorXd>& shapes,
                                          bool closed);

/// The same from eq. 4's gradients (pathEnergy) and the rest Hessians (restHessians) at the path.
std::vector<Eigen::VectorXd> flowTangents(const std::vector<Eigen::VectorXd>& gradients,
                                          const std::vector<Eigen::SparseMatrix<double>>& restHessians, bool closed);

}  // namespace deformation_enrichment::shape_space
