#pragma once
// Acquisition plans and held-out contacts made for a scene rather than written by hand.
//   - autoPlan follows [Seiler14 §6.1]'s use of segmentation as an acquisition guide: k-means regions of
//     d_rho over the touchable display surface (at most kMaxRegions), sites per region in proportion to its
//     area (at least one): the vertex whose rho is nearest the region's mean, then farthest-point spread
//     within the region; at each site an indentation, then indentations with a drag along b_x and b_y.
//   - randomContacts draws held-out interactions uniformly over the touchable surface area (seeded).
// Away from the support: sites and contacts keep two tool radii from every fixed node. Depths and drags
// scale with the tool radius r (indent 0.6 r, drag r), so a small tool on a small object stays gentle.
#include <vector>

#include "deformation_enrichment/acquisition/plan_io.hpp"
#include "deformation_enrichment/acquisition/scene_acquisition.hpp"

namespace deformation_enrichment::acquisition {

/// Interactions per site of autoPlan: press, press + drag along b_x, press + drag along b_y.
constexpr int kPatternsPerSite = 3;
/// Site regions of autoPlan (fewer when there are fewer sites).
constexpr int kMaxRegions = 4;

/// `examples` interactions (>= 1): ceil(examples / kPatternsPerSite) sites, patterns in order until the
/// count is reached. Deterministic. Throws InvalidInputError when the surface has fewer touchable vertices
/// than sites.
std::vector<PlanEntry> autoPlan(SceneAcquisition& acquisition, int examples);

/// `count` held-out interactions drawn with std::mt19937(seed): a point uniform over the touchable surface
/// area, depth uniform in [0.4 r, 0.8 r], and for every other contact a tangential drag of length uniform
/// in [0.2 r, r] in a uniform direction.
std::vector<PlanEntry> randomContacts(const SceneAcquisition& acquisition, int count, unsigned seed);

}  // namespace deformation_enrichment::acquisition
