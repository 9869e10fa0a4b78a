#pragma once
// A ContactEnricher for any display surface, open or closed: rho's density from descriptors::siteDensity
// (the closed surface's interior, the volume around it, or a shell under it), the rest as ContactEnricher.
// The session, de_evaluate and the tests build their enrichers here, so they describe contacts alike.
#include <string>

#include "deformation_enrichment/descriptors/site_density.hpp"
#include "deformation_enrichment/enrichment/contact_enricher.hpp"
#include "deformation_enrichment/mesh/tet_mesh.hpp"

namespace deformation_enrichment::enrichment {

/// The enricher of `surface` (with `volume` around it, or null). The density's grid step and shell are
/// descriptors::forWindow of the options' window scale and sample spacing (as in acquisition).
/// `description` (optional) receives how the density was made. Throws InvalidInputError as siteDensity and
/// ContactEnricher do.
ContactEnricher surfaceEnricher(const mesh::TriangleMesh& surface, const mesh::TetMesh* volume,
                                const ContactEnricherOptions& options, const descriptors::SiteDensityOptions& density,
                                std::string* description = nullptr);

}  // namespace deformation_enrichment::enrichment
