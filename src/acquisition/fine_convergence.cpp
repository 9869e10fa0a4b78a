#include "deformation_enrichment/acquisition/fine_convergence.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>

#include "deformation_enrichment/acquisition/plan_generation.hpp"
#include "deformation_enrichment/acquisition/scene_acquisition.hpp"
#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/barycentric_embedding.hpp"
#include "deformation_enrichment/root_mean_square.hpp"
#include "deformation_enrichment/scenes/fine_model.hpp"

namespace deformation_enrichment::acquisition {
namespace {

void checkFactors(const std::vector<double>& factors, int count) {
  if (factors.empty() || factors.front() != 1.0)
    throw InvalidInputError("fine convergence: the levels must start with 1 (the scene's own fine model)");
  for (std::size_t k = 1; k < factors.size(); ++k)
    if (!(factors[k] > factors[k - 1]))
      throw InvalidInputError("fine convergence: the levels must be ascending, got " + std::to_string(factors[k]) + " after " +
                              std::to_string(factors[k - 1]));
  if (count < 1) throw InvalidInputError("fine convergence: needs at least one held-out interaction");
}

// The display vertices within the stamp radius of each interaction's contact.
std::vector<std::vector<int>> scoredVertices(const SceneAcquisition& acquisition, const std::vector<PlanEntry>& entries) {
  const Eigen::Matrix3Xd& rest = acquisition.fineSurface().vertices;
  std::vector<std::vector<int>> scored;
  for (const PlanEntry& e : entries) {
    const Eigen::Vector3d p = acquisition.contactOf(e).point;
    scored.emplace_back();
    for (Eigen::Index v = 0; v < rest.cols(); ++v)
      if ((rest.col(v) - p).norm() < acquisition.scene().stamp.radius) scored.back().push_back(static_cast<int>(v));
  }
  return scored;
}

double overContacts(const std::vector<FineConvergenceContact>& contacts, std::size_t pair, bool worst) {
  double sum = 0.0, largest = 0.0;
  int n = 0;
  for (const FineConvergenceContact& c : contacts) {
    if (!(c.coarseRms > 0.0) || pair >= c.changeRms.size()) continue;
    const double relative = c.changeRms[pair] / c.coarseRms;
    sum += relative, largest = std::max(largest, relative), ++n;
  }
  return worst ? largest : (n ? sum / n : 0.0);
}

}  // namespace

double FineConvergence::meanRelativeChange(std::size_t pair) const { return overContacts(contacts, pair, false); }
double FineConvergence::worstRelativeChange(std::size_t pair) const { return overContacts(contacts, pair, true); }

scene_file::SceneDescription withFinerFineModel(const scene_file::SceneDescription& scene, double factor,
                                                const Eigen::Matrix3Xd& surfaceVertices, const Eigen::Matrix3Xi& surfaceTriangles) {
  if (!(factor >= 1.0)) throw InvalidInputError("fine convergence: a level must be at least 1, got " + std::to_string(factor));
  scene_file::SceneDescription finer = scene;
  if (finer.procedural) {
    const double perAxis = std::cbrt(factor);
    scene_file::Procedural& p = *finer.procedural;
    for (int k = 0; k < 3; ++k) p.fineCells(k) = static_cast<int>(std::lround(p.fineCells(k) * perAxis));
    p.fineSkinLayers = std::max(1, static_cast<int>(std::lround(p.fineSkinLayers * perAxis)));
  } else {
    const double base = scene.fineMaxVolume > 0.0 ? scene.fineMaxVolume : scenes::defaultFineMaxVolume({surfaceVertices, surfaceTriangles});
    finer.fineMaxVolume = base / factor;
  }
  return finer;
}

FineConvergence fineConvergence(const scene_file::SceneDescription& scene, const std::vector<double>& factors, int count, unsigned seed,
                                const std::function<void(const std::string&)>& progress) {
  checkFactors(factors, count);
  const auto say = [&](const std::string& line) {
    if (progress) progress(line);
  };
  const SceneAcquisition base(scene);
  const std::vector<PlanEntry> entries = randomContacts(base, count, seed);
  const std::vector<std::vector<int>> scored = scoredVertices(base, entries);
  const Eigen::Matrix3Xd& reference = base.fineSurface().vertices;
  FineConvergence out;
  std::vector<Eigen::Matrix3Xd> previous(entries.size());
  for (std::size_t level = 0; level < factors.size(); ++level) {
    std::unique_ptr<SceneAcquisition> finer;
    if (level > 0)
      finer = std::make_unique<SceneAcquisition>(withFinerFineModel(scene, factors[level], reference, base.models().surface.triangles));
    const SceneAcquisition& acquisition = finer ? *finer : base;
    const scenes::SceneModels& m = acquisition.models();
    // The scene's display vertices in this level's fine model (on or next to its boundary).
    const mesh::BarycentricEmbedding at = mesh::embedPoints(m.fine.mesh, reference, std::max(scene.maxOutside, 1e-3));
    FineConvergenceLevel l{factors[level], m.fine.mesh.numVertices(), m.fine.mesh.numTets(), 0.0};
    say("level " + std::to_string(factors[level]) + ": fine " + std::to_string(l.fineTets) + " tets");
    for (std::size_t i = 0; i < entries.size(); ++i) {
      const InteractionResult r = acquisition.simulate(entries[i]);
      if (!r.converged) throw NumericalError("fine convergence: interaction " + std::to_string(i + 1) + " at level " +
                                             std::to_string(factors[level]) + " did not converge: " + r.message);
      l.seconds += r.fineSeconds;
      const Eigen::Matrix3Xd fine = mesh::interpolate(at, m.fine.mesh, r.fineNodes)(Eigen::all, scored[i]);
      if (level == 0) {
        out.contacts.push_back({static_cast<long>(scored[i].size()), rootMeanSquare(r.coarseOnFine(Eigen::all, scored[i]) - fine), {}});
      } else {
        out.contacts[i].changeRms.push_back(rootMeanSquare(fine - previous[i]));
      }
      previous[i] = fine;
      say("  interaction " + std::to_string(i + 1) + " of " + std::to_string(entries.size()) + ": fine solve " +
          std::to_string(r.fineSeconds) + " s");
    }
    out.levels.push_back(l);
  }
  return out;
}

}  // namespace deformation_enrichment::acquisition
