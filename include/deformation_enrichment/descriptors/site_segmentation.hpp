#pragma once
// Site segmentation of [Seiler14 §6.1]: site descriptors at all surface vertices, clustered by k-means with
// d_rho (eq. 9) as the distance. Regions of similar local material neighbourhood (corners, edges, flat
// parts, thin and thick parts) come out as clusters; acquisition uses them to choose example sites.
#include <vector>

#include "deformation_enrichment/descriptors/descriptor_evaluator.hpp"
#include "deformation_enrichment/descriptors/site_density.hpp"
#include "deformation_enrichment/hermite/moment_list.hpp"

namespace deformation_enrichment::descriptors {

struct KMeansOptions {
  int clusters = 4;
  int maxIterations = 200;
  int restarts = 4;  ///< deterministic k-means++ seedings (seeds 1..restarts); the lowest inertia wins
};

struct KMeansResult {
  std::vector<int> labels;                  ///< cluster of every descriptor, 0..clusters-1
  std::vector<hermite::MomentList> centres; ///< cluster means (same layout as the descriptors)
  double inertia = 0.0;                     ///< sum of squared d_rho to the assigned centre
  int iterations = 0;                       ///< Lloyd iterations of the winning restart
};

/// k-means under d_rho: the full-tensor metric is Euclidean after scaling every component by
/// sqrt(multiplicity), so means and assignments are the standard ones in that space. Seeding is k-means++
/// driven by std::mt19937 (a fully specified engine) with fixed seeds: identical input, identical labels.
/// Throws InvalidInputError for no descriptors, mixed layouts, NaN, or clusters outside [1, count].
KMeansResult kMeansSites(const std::vector<hermite::MomentList>& descriptors, const KMeansOptions& options);

struct SiteSegmentation {
  std::vector<int> surfaceToSample;  ///< surface vertex -> sample index (as in the evaluator's surface)
  std::vector<hermite::MomentList> descriptors;  ///< rho in each vertex's stamping frame
  KMeansResult clusters;
};

/// Site descriptors (in their stamping frames) at every surface vertex of the evaluator, then k-means.
SiteSegmentation segmentSites(const DescriptorEvaluator& evaluator, const KMeansOptions& options);

/// One region label per vertex of a rest surface (the enrichment node's ~segment_sites): site descriptors at
/// window scale `scale` (m) over the surface's site density (siteDensity: the closed surface's interior, the
/// volume, or a shell under an open surface), clustered into `regions`. Throws InvalidInputError for a
/// scale that is not positive, regions outside [1, vertices], or a density that cannot be made.
std::vector<int> segmentSurface(const mesh::TriangleMesh& rest, const mesh::TetMesh* volume, int regions, double scale,
                                const SiteDensityOptions& density);

}  // namespace deformation_enrichment::descriptors
