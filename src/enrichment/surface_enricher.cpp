#include "deformation_enrichment/enrichment/surface_enricher.hpp"

namespace deformation_enrichment::enrichment {

ContactEnricher surfaceEnricher(const mesh::TriangleMesh& surface, const mesh::TetMesh* volume,
                                const ContactEnricherOptions& options, const descriptors::SiteDensityOptions& density,
                                std::string* description) {
  descriptors::SiteDensity sites = descriptors::siteDensity(
      surface, volume, descriptors::forWindow(density, options.descriptors.window.scale, options.sampleSpacing));
  if (description) *description = sites.description;
  return ContactEnricher(surface, options, std::move(sites.sampling));
}

}  // namespace deformation_enrichment::enrichment
