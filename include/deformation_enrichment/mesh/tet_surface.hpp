#pragma once
// Boundary surface of a tetrahedral mesh: the faces that belong to exactly one tet, oriented outwards.
#include <Eigen/Core>
#include <vector>

#include "deformation_enrichment/mesh/tet_mesh.hpp"
#include "deformation_enrichment/mesh/triangle_mesh.hpp"

namespace deformation_enrichment::mesh {

struct TetSurface {
  TriangleMesh surface;                 ///< compact surface mesh (only boundary vertices)
  std::vector<int> surfaceToVolume;     ///< surface vertex index -> tet-mesh vertex index
};

/// Extracts the boundary faces of a positively oriented tet mesh (throws InvalidInputError if empty).
TetSurface extractSurface(const TetMesh& volume);

}  // namespace deformation_enrichment::mesh
