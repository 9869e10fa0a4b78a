#include "deformation_enrichment/enrichment/material_similarity.hpp"

#include <cmath>
#include <vector>

namespace deformation_enrichment::enrichment {

double materialSimilarity(const scene_file::SceneDescription& source, const scene_file::SceneDescription& target) {
  const auto skinYoung = [](const scene_file::SceneDescription& s) { return s.skin ? s.skin->material.young : s.material.young; };
  std::vector<double> logRatios{std::log(target.material.young / source.material.young),
                                std::log(skinYoung(target) / skinYoung(source))};
  if (source.skin && target.skin) logRatios.push_back(std::log(target.skin->thickness / source.skin->thickness));
  double squared = 0.0;
  for (double r : logRatios) squared += r * r;
  squared /= static_cast<double>(logRatios.size());
  return std::exp(-squared / (2.0 * kMaterialSigma * kMaterialSigma));
}

}  // namespace deformation_enrichment::enrichment
