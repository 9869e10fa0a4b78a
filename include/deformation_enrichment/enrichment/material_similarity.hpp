#pragma once
// Transfer across objects needs "similar material" ([Seiler14 §1, §5]): the site descriptor sees geometry
// only, so examples of a stiffer or softer tissue look alike and carry detail of the wrong size. The
// material similarity of two scenes, f = exp(-D^2 / (2 sigma^2)) with D^2 the mean squared log ratio of
// bulk Young's modulus, skin Young's modulus and skin thickness (a missing skin counts as the bulk's
// modulus and a thickness of zero is skipped), scales the detail a set adds on another scene: 1 for the
// same material, 0.61 at a factor of 1.5 (sigma = ln 1.5) and 0.05 at a factor of 2.2.
#include "deformation_enrichment/scene_file/scene_description.hpp"

namespace deformation_enrichment::enrichment {

constexpr double kMaterialSigma = 0.4054651081081644;  ///< ln 1.5

double materialSimilarity(const scene_file::SceneDescription& source, const scene_file::SceneDescription& target);

}  // namespace deformation_enrichment::enrichment
