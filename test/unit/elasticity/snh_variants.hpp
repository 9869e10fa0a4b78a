#pragma once
// Both forms of the Stable Neo-Hookean energy the tests check: the paper's and the production one.
#include "deformation_enrichment/elasticity/stable_neo_hookean.hpp"

inline constexpr deformation_enrichment::elasticity::SnhVariant kSnhVariants[] = {
    deformation_enrichment::elasticity::SnhVariant::Paper, deformation_enrichment::elasticity::SnhVariant::Production};
