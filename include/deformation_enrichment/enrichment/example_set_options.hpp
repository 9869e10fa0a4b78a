#pragma once
// The run-time descriptor options an example set was acquired with. Examples and run-time contacts must be
// described identically ([Seiler14 §5] compares rho, mu computed the same way: window scale h, cut-off,
// quadrature, interior sampling, orders, stamp radius), so the node, acquisition and de_evaluate all take
// their ContactEnricherOptions from the set through optionsFor().
#include "deformation_enrichment/enrichment/contact_enricher.hpp"
#include "deformation_enrichment/examples/example.hpp"
#include "deformation_enrichment/scene_file/scene_description.hpp"

namespace deformation_enrichment::enrichment {

/// `defaults` with the descriptor options of a scene file applied (window, cut-off, quadrature, interior
/// sampling, stamp radius).
ContactEnricherOptions optionsFor(const scene_file::SceneDescription& scene, ContactEnricherOptions defaults = {});

/// `defaults` with everything the set records applied: its provenance's scene (or, for sets without provenance,
/// the named metadata entries they have), the orders rho and mu of its examples and
/// their stamp radius. Run-time-only knobs of `defaults` (gain, rim band, magnitude scaling) stay. Throws
/// InvalidInputError for an empty set, examples of mixed layouts or radii, or a recorded value that is not
/// finite and positive.
ContactEnricherOptions optionsFor(const examples::ExampleSet& set, ContactEnricherOptions defaults = {});

}  // namespace deformation_enrichment::enrichment
