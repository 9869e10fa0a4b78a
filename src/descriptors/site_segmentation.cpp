#include "deformation_enrichment/descriptors/site_segmentation.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>

#include "deformation_enrichment/descriptors/site_descriptor_table.hpp"
#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::descriptors {

namespace {
struct LloydRun {
  std::vector<int> labels;
  Eigen::MatrixXd centres;
  double inertia = 0.0;
  int iterations = 0;
};

// One Lloyd run from k-means++ seeds; columns of `points` are descriptors in the metric-scaled space.
LloydRun lloyd(const Eigen::MatrixXd& points, int clusters, int maxIterations, unsigned seed) {
  const Eigen::Index count = points.cols();
  std::mt19937 engine(seed);
  auto uniformIndex = [&engine, count]() {
    return std::min<Eigen::Index>(count - 1, static_cast<Eigen::Index>(engine() / 4294967296.0 * count));
  };

  LloydRun run;
  run.centres.resize(points.rows(), clusters);
  run.centres.col(0) = points.col(uniformIndex());
  Eigen::VectorXd nearest = (points.colwise() - run.centres.col(0)).colwise().squaredNorm().transpose();
  for (int c = 1; c < clusters; ++c) {
    // k-means++: next seed drawn with probability proportional to the squared distance to the chosen ones.
    const double total = nearest.sum();
    Eigen::Index pick = 0;
    if (total > 0.0) {
      double target = engine() / 4294967296.0 * total;
      for (pick = 0; pick < count - 1; ++pick) {
        target -= nearest[pick];
        if (target < 0.0) break;
      }
    } else {
      pick = uniformIndex();
    }
    run.centres.col(c) = points.col(pick);
    nearest = nearest.cwiseMin((points.colwise() - run.centres.col(c)).colwise().squaredNorm().transpose());
  }

  run.labels.assign(count, -1);
  Eigen::VectorXd distance(count);
  for (run.iterations = 1; run.iterations <= maxIterations; ++run.iterations) {
    bool changed = false;
    for (Eigen::Index m = 0; m < count; ++m) {
      Eigen::Index best = 0;
      distance[m] = (run.centres.colwise() - points.col(m)).colwise().squaredNorm().minCoeff(&best);
      if (run.labels[m] != static_cast<int>(best)) {
        run.labels[m] = static_cast<int>(best);
        changed = true;
      }
    }
    if (!changed) break;
    Eigen::MatrixXd sums = Eigen::MatrixXd::Zero(points.rows(), clusters);
    Eigen::VectorXd sizes = Eigen::VectorXd::Zero(clusters);
    for (Eigen::Index m = 0; m < count; ++m) {
      sums.col(run.labels[m]) += points.col(m);
      sizes[run.labels[m]] += 1.0;
    }
    for (int c = 0; c < clusters; ++c) {
      if (sizes[c] > 0.0) {
        run.centres.col(c) = sums.col(c) / sizes[c];
      } else {
        // An empty cluster takes the point worst served by its centre.
        Eigen::Index worst = 0;
        distance.maxCoeff(&worst);
        run.centres.col(c) = points.col(worst);
        distance[worst] = 0.0;
      }
    }
  }
  run.iterations = std::min(run.iterations, maxIterations);
  for (Eigen::Index m = 0; m < count; ++m)
    run.inertia += (points.col(m) - run.centres.col(run.labels[m])).squaredNorm();
  return run;
}
}  // namespace

KMeansResult kMeansSites(const std::vector<hermite::MomentList>& descriptors, const KMeansOptions& options) {
  if (descriptors.empty()) throw InvalidInputError("k-means: no descriptors");
  const int count = static_cast<int>(descriptors.size());
  if (options.clusters < 1 || options.clusters > count)
    throw InvalidInputError("k-means: " + std::to_string(options.clusters) + " clusters for " +
                            std::to_string(count) + " descriptors");
  if (options.maxIterations < 1 || options.restarts < 1)
    throw InvalidInputError("k-means: iterations and restarts must be positive");
  const hermite::MomentList& first = descriptors.front();
  const Eigen::VectorXd metric = first.multiplicities().cwiseSqrt();
  Eigen::MatrixXd points(first.values().size(), count);
  for (int m = 0; m < count; ++m) {
    const hermite::MomentList& d = descriptors[m];
    if (d.firstOrder() != first.firstOrder() || d.lastOrder() != first.lastOrder() ||
        d.channels() != first.channels())
      throw InvalidInputError("k-means: descriptor " + std::to_string(m) + " has a different layout");
    if (!d.values().allFinite()) throw InvalidInputError("k-means: descriptor " + std::to_string(m) + " is not finite");
    // Scaling by sqrt(multiplicity) turns d_rho (eq. 9) into the Euclidean distance.
    points.col(m) = metric.cwiseProduct(d.values());
  }
  LloydRun best;
  best.inertia = std::numeric_limits<double>::infinity();
  for (int restart = 1; restart <= options.restarts; ++restart) {
    LloydRun run = lloyd(points, options.clusters, options.maxIterations, static_cast<unsigned>(restart));
    if (run.inertia < best.inertia) best = std::move(run);
  }
  KMeansResult result;
  result.labels = std::move(best.labels);
  result.inertia = best.inertia;
  result.iterations = best.iterations;
  for (int c = 0; c < options.clusters; ++c) {
    hermite::MomentList centre = first;
    centre.values() = best.centres.col(c).cwiseQuotient(metric);
    result.centres.push_back(std::move(centre));
  }
  return result;
}

SiteSegmentation segmentSites(const DescriptorEvaluator& evaluator, const KMeansOptions& options) {
  SiteSegmentation segmentation;
  segmentation.descriptors = SiteDescriptorTable(evaluator).framedDescriptors();
  segmentation.surfaceToSample = evaluator.surfaceToSample();
  segmentation.clusters = kMeansSites(segmentation.descriptors, options);
  return segmentation;
}

std::vector<int> segmentSurface(const mesh::TriangleMesh& rest, const mesh::TetMesh* volume, int regions, double scale,
                                const SiteDensityOptions& density) {
  if (!(scale > 0.0) || !std::isfinite(scale)) throw InvalidInputError("site segmentation: the window scale must be positive");
  if (regions < 1 || regions > rest.numVertices())
    throw InvalidInputError("site segmentation: regions must be in [1, " + std::to_string(rest.numVertices()) +
                            "] (one per rest vertex at most), got " + std::to_string(regions));
  DescriptorOptions options;
  options.window.scale = scale;
  DescriptorEvaluator evaluator(siteDensity(rest, volume, density).sampling, rest, {}, options);
  KMeansOptions kmeans;
  kmeans.clusters = regions;
  return segmentSites(evaluator, kmeans).clusters.labels;
}

}  // namespace deformation_enrichment::descriptors
