#pragma once
// The small slab surface and enricher options the ContactEnricher unit tests share.
#include "deformation_enrichment/enrichment/contact_enricher.hpp"
#include "deformation_enrichment/mesh/grid_tet_mesh.hpp"
#include "deformation_enrichment/mesh/tet_surface.hpp"

namespace de_test {

// 10 x 10 x 2 cm, 16 x 16 x 3 cells (6.25 mm on top).
inline deformation_enrichment::mesh::TriangleMesh slabSurface() {
  namespace mesh = deformation_enrichment::mesh;
  return mesh::extractSurface(mesh::gridTetMesh(Eigen::Vector3d(-0.05, -0.05, 0.0), Eigen::Vector3d(0.05, 0.05, 0.02),
                                                Eigen::Vector3i(16, 16, 3)))
      .surface;
}

// h = 8 mm, R = 2 cm, interior samples every 3 mm.
inline deformation_enrichment::enrichment::ContactEnricherOptions enricherOptions() {
  deformation_enrichment::enrichment::ContactEnricherOptions o;
  o.descriptors.window.scale = 0.008;
  o.stampRadius = 0.02;
  o.sampleSpacing = 0.003;
  return o;
}

}  // namespace de_test
