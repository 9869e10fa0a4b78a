#pragma once
// Builds a DescriptorEvaluator from a file, for the command-line tools and the ROS layer:
//   <base>.node (+ <base>.ele beside it): TetGen tet mesh; samples = vertices with lumped volumes;
//   *.obj / *.ply: closed triangle surface; samples = interior grid (sampleClosedSurfaceInterior) of the
//   given spacing (default h / 4), each with the cell volume. A surface input carries no vertex
//   correspondence to its interior samples, so only site descriptors can be evaluated on it.
#include <string>

#include "deformation_enrichment/descriptors/descriptor_evaluator.hpp"

namespace deformation_enrichment::descriptors {

struct LoadedObject {
  DescriptorEvaluator evaluator;
  bool volumetric = false;  ///< true for a tet mesh (deformation descriptors possible)
  std::string sampling;     ///< human-readable description of how the samples were made
};

/// Throws IoError for unreadable files, InvalidInputError for unsupported extensions or bad meshes.
LoadedObject loadDescriptorObject(const std::string& path, const DescriptorOptions& options,
                                  double surfaceSampleSpacing = 0.0);

}  // namespace deformation_enrichment::descriptors
