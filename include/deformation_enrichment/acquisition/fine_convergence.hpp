#pragma once
// Is the fine model converged? Every accuracy figure measures the enrichment against the fine solve of a
// held-out interaction; if refining the fine model moves that truth by as much as the enrichment's
// remaining error, the figures measure mesh noise. fineConvergence solves the same interactions with the
// fine model at several tet counts and reports how far the truth moves between consecutive levels, on
// the display vertices within the stamp radius of the contact, as a fraction of the coarse model's error
// there (the denominator of the accuracy ratio). docs/accuracy.md holds the measurements.
#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

#include "deformation_enrichment/scene_file/scene_description.hpp"

namespace deformation_enrichment::acquisition {

struct FineConvergenceLevel {
  double factor = 1.0;  ///< asked tet-count factor over the scene's fine model
  Eigen::Index fineNodes = 0, fineTets = 0;
  double seconds = 0.0;  ///< fine solves of every interaction at this level
};

struct FineConvergenceContact {
  long vertices = 0;               ///< display vertices scored (within the stamp radius of the contact)
  double coarseRms = 0.0;          ///< RMS of coarse - fine (the scene's own fine model), metres
  std::vector<double> changeRms;   ///< per pair of consecutive levels: RMS of the fine solutions' difference
};

struct FineConvergence {
  std::vector<FineConvergenceLevel> levels;
  std::vector<FineConvergenceContact> contacts;
  /// Mean and largest over contacts of changeRms[pair] / coarseRms.
  double meanRelativeChange(std::size_t pair) const;
  double worstRelativeChange(std::size_t pair) const;
};

/// The scene with its fine model about `factor` times as many tets: a procedural scene's fine cells and
/// skin layers scaled by factor^(1/3) per axis; a file scene's fine max_volume (or its default for
/// `surface`) divided by `factor`. Throws InvalidInputError for a factor below 1.
scene_file::SceneDescription withFinerFineModel(const scene_file::SceneDescription& scene, double factor,
                                                const Eigen::Matrix3Xd& surfaceVertices,
                                                const Eigen::Matrix3Xi& surfaceTriangles);

/// Solves `count` random held-out interactions (randomContacts, `seed`) with the scene's coarse model and
/// with its fine model at every factor of `factors` (ascending, the first 1), and compares the fine
/// solutions level by level at the scene's display vertices (found in each finer model by barycentric
/// embedding). `progress(text)` (optional) sees one line per level and interaction. Throws
/// InvalidInputError for factors that are not ascending from 1 or a count below 1.
FineConvergence fineConvergence(const scene_file::SceneDescription& scene, const std::vector<double>& factors, int count,
                                unsigned seed, const std::function<void(const std::string&)>& progress = {});

}  // namespace deformation_enrichment::acquisition
