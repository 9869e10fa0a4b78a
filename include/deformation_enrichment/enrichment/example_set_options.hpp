#pragma once
// The run-time descriptor options an example set was acquired with, recorded in its metadata. Examples and
// run-time contacts must be described identically ([Seiler14 §5] compares rho, mu computed the same way:
// window scale h, cut-off, quadrature, interior sampling, orders, stamp radius), so the node, acquisition
// and de_evaluate all take their ContactEnricherOptions from the set through optionsFor().
#include <map>
#include <string>

#include "deformation_enrichment/enrichment/contact_enricher.hpp"
#include "deformation_enrichment/examples/example.hpp"

namespace deformation_enrichment::enrichment {

/// The metadata entries (SI units) that record how `options` describes contacts; acquisition writes them.
std::map<std::string, double> descriptorMetadata(const ContactEnricherOptions& options);

/// `defaults` with everything the set records applied: the metadata of descriptorMetadata (sets written
/// before an entry existed keep the default for it), the orders rho and mu of its examples and their stamp
/// radius. Run-time-only knobs of `defaults` (gain, rim band, magnitude scaling) stay. Throws
/// InvalidInputError for an empty set, examples of mixed layouts or radii, or a recorded value that is not
/// finite and positive.
ContactEnricherOptions optionsFor(const examples::ExampleSet& set, ContactEnricherOptions defaults = {});

}  // namespace deformation_enrichment::enrichment
