#pragma once
// A mesh state: the positions of a rest mesh's vertices at one instant (float32, as they travel).
#include <Eigen/Core>

namespace deformation_enrichment::mesh {

/// Throws InvalidInputError naming the problem unless `positions` has exactly `restVertexCount` columns
/// and every coordinate is finite.
void validateMeshState(const Eigen::Ref<const Eigen::Matrix3Xf>& positions, Eigen::Index restVertexCount);

}  // namespace deformation_enrichment::mesh
