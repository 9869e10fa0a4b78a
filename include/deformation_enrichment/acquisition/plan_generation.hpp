#pragma once
// Acquisition plans and held-out contacts made for a scene rather than written by hand.
//   - autoPlan is a nested sequence: its first N interactions are autoPlan(N) for every N, so one
//     acquisition of the largest set gives every smaller one (learning curves, a set that grows). Sites are
//     the touchable display vertices in farthest-point order (the first the one nearest the centroid of the
//     touchable surface): every prefix covers the surface as evenly as its size allows, which is what
//     contacts anywhere on it need ([Seiler14 §6.1] places sites by segmentation instead; segmentation
//     regions are not nested). Depths and drags follow a Halton sequence [Halton60] over the range of
//     interactions the user will make: depth in [0.3 r, 0.9 r], every other interaction a drag of length in
//     [0.2 r, r] at an angle to the site's rest frame B.
//   - randomContacts draws held-out interactions uniformly over the touchable surface area (seeded).
// Away from the support: sites and contacts keep two tool radii from every fixed node. Depths and drags
// scale with the tool radius r, so a small tool on a small object stays gentle.
#include <vector>

#include <optional>

#include "deformation_enrichment/acquisition/plan_io.hpp"
#include "deformation_enrichment/acquisition/scene_acquisition.hpp"

namespace deformation_enrichment::acquisition {

/// Interactions of a scene's automatic plan when no count is asked for.
constexpr int kDefaultAutoPlanSize = 12;

/// The first `examples` interactions (>= 1) of the scene's nested plan. Deterministic. Throws
/// InvalidInputError when the surface has fewer touchable vertices than interactions.
std::vector<PlanEntry> autoPlan(SceneAcquisition& acquisition, int examples);

/// The plan a scene is acquired with: its automatic plan (scene plan "auto": the first `examples`, default
/// kDefaultAutoPlanSize) or its CSV (the first `examples` lines when given). Throws InvalidInputError when
/// `examples` exceeds the CSV's lines, IoError for an unreadable CSV.
std::vector<PlanEntry> scenePlan(SceneAcquisition& acquisition, std::optional<int> examples = std::nullopt);

/// `count` held-out interactions drawn with std::mt19937(seed): a point uniform over the touchable surface
/// area, depth uniform in [0.4 r, 0.8 r], and for every other contact a tangential drag of length uniform
/// in [0.2 r, r] in a uniform direction.
std::vector<PlanEntry> randomContacts(const SceneAcquisition& acquisition, int count, unsigned seed);

}  // namespace deformation_enrichment::acquisition
