#include "deformation_enrichment/enrichment/example_set_options.hpp"

#include <cmath>

#include "deformation_enrichment/enrichment/descriptor_order.hpp"
#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::enrichment {

namespace {
constexpr const char* kWindowScale = "window_scale_m";
constexpr const char* kWindowCutoff = "window_cutoff_h";
constexpr const char* kSampleSpacing = "site_sample_spacing_m";
constexpr const char* kStampRadius = "stamp_radius_m";
constexpr const char* kAverageQuadrature = "average_quadrature";

// Applies a recorded positive length (or count of h) when the set has it.
void applyPositive(const std::map<std::string, double>& metadata, const char* key, double& value) {
  const auto it = metadata.find(key);
  if (it == metadata.end()) return;
  if (!(it->second > 0.0) || !std::isfinite(it->second))
    throw InvalidInputError("example set metadata: " + std::string(key) + " must be finite and positive, got " +
                            std::to_string(it->second));
  value = it->second;
}
}  // namespace

std::map<std::string, double> descriptorMetadata(const ContactEnricherOptions& options) {
  return {{kWindowScale, options.descriptors.window.scale},
          {kWindowCutoff, options.descriptors.window.cutoff},
          {kSampleSpacing, options.sampleSpacing},
          {kStampRadius, options.stampRadius},
          {kAverageQuadrature, options.descriptors.window.quadrature == descriptors::Quadrature::Average ? 1.0 : 0.0}};
}

ContactEnricherOptions optionsFor(const examples::ExampleSet& set, ContactEnricherOptions defaults) {
  if (set.examples.empty()) throw InvalidInputError("example set has no examples");
  const auto& metadata = set.metadata.material;
  applyPositive(metadata, kWindowScale, defaults.descriptors.window.scale);
  applyPositive(metadata, kWindowCutoff, defaults.descriptors.window.cutoff);
  applyPositive(metadata, kSampleSpacing, defaults.sampleSpacing);
  const auto average = metadata.find(kAverageQuadrature);
  if (average != metadata.end())
    defaults.descriptors.window.quadrature = average->second == 1.0 ? descriptors::Quadrature::Average : descriptors::Quadrature::Volume;
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
