#include "deformation_enrichment/enrichment/example_set_options.hpp"

#include <cmath>
#include <map>
#include <string>

#include "deformation_enrichment/enrichment/descriptor_order.hpp"
#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::enrichment {

namespace {

// Sets without provenance name their descriptor options in the metadata map.
void applyLegacyMetadata(const std::map<std::string, double>& metadata, ContactEnricherOptions& o) {
  const auto positive = [&](const char* key, double& value) {
    const auto it = metadata.find(key);
    if (it == metadata.end()) return;
    if (!(it->second > 0.0) || !std::isfinite(it->second))
      throw InvalidInputError("example set metadata: " + std::string(key) + " must be finite and positive, got " +
                              std::to_string(it->second));
    value = it->second;
  };
  positive("window_scale_m", o.descriptors.window.scale);
  positive("window_cutoff_h", o.descriptors.window.cutoff);
  positive("site_sample_spacing_m", o.sampleSpacing);
  const auto average = metadata.find("average_quadrature");
  if (average != metadata.end())
    o.descriptors.window.quadrature = average->second == 1.0 ? descriptors::Quadrature::Average : descriptors::Quadrature::Volume;
}

}  // namespace

ContactEnricherOptions optionsFor(const scene_file::SceneDescription& scene, ContactEnricherOptions defaults) {
  defaults.descriptors.window.scale = scene.descriptors.windowScale;
  defaults.descriptors.window.cutoff = scene.descriptors.cutoff;
  defaults.descriptors.window.quadrature =
      scene.descriptors.averageQuadrature ? descriptors::Quadrature::Average : descriptors::Quadrature::Volume;
  defaults.sampleSpacing = scene.descriptors.sampleSpacing;
  defaults.stampRadius = scene.stamp.radius;
  return defaults;
}

ContactEnricherOptions optionsFor(const examples::ExampleSet& set, ContactEnricherOptions defaults) {
  if (set.examples.empty()) throw InvalidInputError("example set has no examples");
  if (set.metadata.provenance)
    defaults = optionsFor(set.metadata.provenance->scene, defaults);
  else
    applyLegacyMetadata(set.metadata.material, defaults);
  const examples::Example& first = set.examples.front();
  for (const examples::Example& e : set.examples) {
    if (e.stampRadius != first.stampRadius)
      throw InvalidInputError("example set mixes stamp radii " + std::to_string(first.stampRadius) + " and " +
                              std::to_string(e.stampRadius) + " m");
    if (e.rho.firstOrder() != first.rho.firstOrder() || e.rho.lastOrder() != first.rho.lastOrder())
      throw InvalidInputError("example set mixes site descriptor orders");
  }
  defaults.stampRadius = first.stampRadius;
  defaults.descriptors.siteOrder = first.rho.lastOrder();
  defaults.descriptors.deformationOrder = deformationOrder(set);
  return defaults;
}

}  // namespace deformation_enrichment::enrichment
