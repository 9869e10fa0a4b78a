#pragma once
// A small slab scene for acquisition tests: coarse 6 x 6 x 1 (+1 skin layer), fine 12 x 12 x 2 (+1), one
// indent and drag step, 16-node stamps: a whole acquisition in about a second.
#include "deformation_enrichment/scene_file/scene_description.hpp"

namespace de_test {

inline deformation_enrichment::scene_file::SceneDescription tinySlab() {
  namespace sf = deformation_enrichment::scene_file;
  sf::SceneDescription d = sf::readSceneFile(sf::findSceneFile("slab"));
  d.procedural->coarseCells = Eigen::Vector3i(6, 6, 1);
  d.procedural->fineCells = Eigen::Vector3i(12, 12, 2);
  d.procedural->fineSkinLayers = 1;
  d.solve.indentSteps = 1;
  d.solve.dragSteps = 1;
  d.stamp.resolution = 16;
  d.descriptors.windowScale = 0.008;
  d.descriptors.sampleSpacing = 0.004;
  return d;
}

}  // namespace de_test
