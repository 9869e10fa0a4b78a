#pragma once
// Structured tetrahedral mesh of a box: a rectilinear grid of cells, each split into six tets that share
// the cell's main diagonal (Kuhn subdivision), so neighbouring cells conform without any flipping.
#include <Eigen/Core>

#include "deformation_enrichment/mesh/tet_mesh.hpp"

namespace deformation_enrichment::mesh {

/// Grid over the given strictly increasing axis coordinates (at least two per axis; spacing may vary,
/// which gives graded, non-uniform meshes). Vertex (i, j, k) has index i + nx * (j + ny * k).
/// Throws InvalidInputError for fewer than two or non-increasing coordinates.
TetMesh gridTetMesh(const Eigen::VectorXd& xs, const Eigen::VectorXd& ys, const Eigen::VectorXd& zs);

/// Uniform grid of cells over [lo, hi] with the given number of cells per axis.
TetMesh gridTetMesh(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, const Eigen::Vector3i& cells);

}  // namespace deformation_enrichment::mesh
