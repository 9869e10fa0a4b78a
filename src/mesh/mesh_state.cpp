#include "deformation_enrichment/mesh/mesh_state.hpp"

#include <cmath>
#include <string>

#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::mesh {

void validateMeshState(const Eigen::Ref<const Eigen::Matrix3Xf>& positions, Eigen::Index restVertexCount) {
  if (positions.cols() != restVertexCount)
    throw InvalidInputError("mesh state has " + std::to_string(positions.cols()) + " points but the rest mesh has " +
                            std::to_string(restVertexCount) + " vertices");
  // x * 0 is NaN exactly for non-finite x; the sum over the flat buffer is vectorised (allFinite and a
  // 3 x n sum go column by column).
  const bool finite = positions.outerStride() == 3
                          ? std::isfinite((Eigen::Map<const Eigen::ArrayXf>(positions.data(), positions.size()) * 0.0f).sum())
                          : positions.allFinite();
  if (!finite) {
    for (Eigen::Index v = 0; v < positions.cols(); ++v) {
      if (!positions.col(v).allFinite())
        throw InvalidInputError("mesh state point " + std::to_string(v) + " is not finite (NaN or Inf)");
    }
  }
}

}  // namespace deformation_enrichment::mesh
