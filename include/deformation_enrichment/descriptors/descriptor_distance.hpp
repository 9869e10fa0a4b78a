#pragma once
// Dissimilarities of [Seiler14]: d_rho = |rho - rho'| (eq. 9) and d_u = 1 - <mu, mu'> / (|mu| |mu'|) (eq. 14),
// with |.| = sqrt(<., .>) (the paper's shorthand drops the square roots). Both descriptors must be
// expressed in the same frame (their stamping frames) beforehand.
#include "deformation_enrichment/hermite/moment_list.hpp"

namespace deformation_enrichment::descriptors {

/// eq. (9). Throws InvalidInputError when the layouts differ or a value is not finite.
double siteDistance(const hermite::MomentList& rho, const hermite::MomentList& rhoOther);

/// eq. (14) in [0, 2]; both zero -> 0, exactly one zero -> 1. Throws like siteDistance.
double deformationDistance(const hermite::MomentList& mu, const hermite::MomentList& muOther);

}  // namespace deformation_enrichment::descriptors
