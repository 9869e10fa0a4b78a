#pragma once
// Cheaper variants of an acquired example set, for the run-time-vs-error trade-off ([Seiler14]
// Fig. 7 and §7): fewer stamp nodes, lower Hermite orders, fewer examples. Each variant is exactly what
// acquisition at that setting would store, up to the stamp re-sampling noted below.
#include "deformation_enrichment/examples/example.hpp"

namespace deformation_enrichment::enrichment {

/// Every stamp re-sampled to resolution x resolution nodes over the same square by bilinear look-up at
/// the new node positions (rasterisation at that resolution samples the same patch field at the same
/// nodes; the look-up interpolates the finer grid instead of the patch). Throws InvalidInputError for
/// resolution < 2 or an invalid example.
examples::ExampleSet withStampResolution(const examples::ExampleSet& set, int resolution);

/// Site moments rho_0..rho_siteOrder and deformation moments mu_1..mu_deformationOrder kept, higher orders
/// dropped. Moments of each order are independent of the others, so this equals describing at the lower
/// orders. Throws InvalidInputError when an example holds fewer orders than asked for.
examples::ExampleSet withHermiteOrders(const examples::ExampleSet& set, int siteOrder, int deformationOrder);

}  // namespace deformation_enrichment::enrichment
