#include "deformation_enrichment/mesh/mesh_state.hpp"

#include <string>

#include "deformation_enrichment/all_finite.hpp"
#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::mesh {

void validateMeshState(const Eigen::Ref<const Eigen::Matrix3Xf>& positions, Eigen::Index restVertexCount) {
  if (positions.cols() != restVertexCount)
    throw InvalidInputError("mesh state has " + std::to_string(positions.cols()) + " points but the rest mesh has " +
                            std::to_string(restVertexCount) + " vertices");
  const bool finite = positions.outerStride() == 3 ? allFiniteValues(positions) : positions.allFinite();
  if (!finite) {
    for (Eigen::Index v = 0; v < positions.cols(); ++v) {
      if (!positions.col(v).allFinite())
        throw InvalidInputError("mesh state point " + std::to_string(v) + " is not finite (NaN or Inf)");
    }
  }
}

}  // namespace deformation_enrichment::mesh
