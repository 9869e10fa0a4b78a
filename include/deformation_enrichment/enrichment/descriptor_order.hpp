#pragma once
// The Hermite order N of the deformation descriptor as a run-time knob. mu_n (eq. 11) is the projection of
// u_bar onto the order-n Hermite functions; F, R and t (eq. 10) do not depend on N, so mu_1..mu_M of an
// order-N descriptor (M <= N) are exactly the order-M descriptor. An example set built with order N can
// therefore run at any order M <= N by truncating the examples' mu (the run time computes order M); a
// higher order would need moments the set never stored.
#include "deformation_enrichment/examples/example.hpp"
#include "deformation_enrichment/hermite/moment_list.hpp"

namespace deformation_enrichment::enrichment {

/// Orders firstOrder()..lastOrder of `moments`, every channel. Throws InvalidInputError when lastOrder lies
/// outside [firstOrder(), moments.lastOrder()].
hermite::MomentList truncatedMoments(const hermite::MomentList& moments, int lastOrder);

/// The highest mu order every example of `set` stores (the order the set was built with). Throws
/// InvalidInputError for an empty set or examples whose mu layouts differ.
int deformationOrder(const examples::ExampleSet& set);

/// `set` with every mu truncated to orders 1..order. Throws InvalidInputError (naming both orders) when
/// order is below 1 or above deformationOrder(set).
examples::ExampleSet withDeformationOrder(const examples::ExampleSet& set, int order);

}  // namespace deformation_enrichment::enrichment
