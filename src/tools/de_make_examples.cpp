// de_make_examples: acquires an example set on the slab scene (paper 000 §3). For every plan line it runs
// the coarse and the fine simulation, takes d = fine - coarse on the fine surface and stores descriptors
// and stamp. The set is rewritten after every example, so an interrupted run resumes where it stopped
// (examples already in SET with the same contact and pattern are kept, not recomputed).
#include <CLI/CLI.hpp>
#include <filesystem>
#include <iostream>

#include "deformation_enrichment/acquisition/example_generation.hpp"
#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/examples/example_set_io.hpp"

using namespace deformation_enrichment;

namespace {

bool samePattern(const examples::Example& e, const acquisition::PlanEntry& p) {
  return (e.contact - p.point).norm() < 1e-9 && std::abs(e.pattern.indentDepth - p.depth) < 1e-12 &&
         (e.pattern.drag - p.drag).norm() < 1e-12;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Acquire an example set (coarse vs fine simulations) for a scene"};
  std::string sceneName = "slab", output, planPath;
  int resolution = 64;
  double toolRadius = acquisition::SlabAcquisitionOptions().toolRadius;
  std::vector<int> coarseCells{10, 10, 2}, fineCells{24, 24, 4};
  app.add_option("--scene", sceneName, "scene (slab)")->check(CLI::IsMember({"slab"}));
  app.add_option("--output", output, "example set directory")->required();
  app.add_option("--plan", planPath, "CSV x,y,z,depth,dx,dy,dz per interaction (default: built-in slab plan)");
  app.add_option("--stamp-resolution", resolution, "stamp nodes per side");
  app.add_option("--coarse-cells", coarseCells, "coarse slab cells x y bulk-z (+1 skin layer)")->expected(3);
  app.add_option("--fine-cells", fineCells, "fine slab cells x y bulk-z (+2 skin layers)")->expected(3);
  app.add_option("--tool-radius", toolRadius, "tool footprint radius (m)");
  std::string toolModel = "penalty";
  app.add_option("--tool-model", toolModel, "penalty (smooth footprint springs) or dirichlet (vertices under the tip)")
      ->check(CLI::IsMember({"penalty", "dirichlet"}));
  CLI11_PARSE(app, argc, argv);
  try {
    const std::vector<acquisition::PlanEntry> plan = planPath.empty() ? acquisition::defaultSlabPlan() : acquisition::readPlan(planPath);
    acquisition::SlabAcquisitionOptions options;
    options.stampResolution = resolution;
    options.toolRadius = toolRadius;
    options.toolModel = toolModel == "penalty" ? acquisition::ToolModel::Penalty : acquisition::ToolModel::Dirichlet;
    options.coarse.cells = Eigen::Vector3i(coarseCells[0], coarseCells[1], coarseCells[2]);
    options.fine.cells = Eigen::Vector3i(fineCells[0], fineCells[1], fineCells[2]);
    std::cerr << "building coarse and fine slabs, embedding and site sampling...\n";
    acquisition::SlabAcquisition acq(options);
    examples::ExampleSet previous;
    if (std::filesystem::exists(std::filesystem::path(output) / examples::kManifestFile)) {
      try {
        previous = examples::loadExampleSet(output);
        std::cerr << "resuming: " << previous.examples.size() << " examples already in " << output << "\n";
      } catch (const std::exception& e) {
        std::cerr << "existing set not reusable (" << e.what() << "), starting over\n";
      }
    }
    examples::ExampleSet set;
    set.metadata.scene = sceneName;
    set.metadata.material = acq.materialMetadata();
    set.metadata.description = "de_make_examples: coarse vs fine slab (cells in the material metadata), SNH";
    for (std::size_t i = 0; i < plan.size(); ++i) {
      const acquisition::PlanEntry& entry = plan[i];
      const examples::Example* done = nullptr;
      for (const auto& e : previous.examples)
        if (samePattern(e, entry) && e.stamp.rows == resolution && previous.metadata.material == set.metadata.material) done = &e;
      if (done) {
        set.examples.push_back(*done);
        std::cerr << "[" << i + 1 << "/" << plan.size() << "] already acquired, skipped\n";
        continue;
      }
      const acquisition::InteractionResult r = acq.simulate(entry);
      if (!r.converged) std::cerr << "  warning: " << r.message << "\n";
      set.examples.push_back(acq.makeExample(entry, r));
      examples::saveExampleSet(set, output);  // after every example: resumable
      std::cerr << "[" << i + 1 << "/" << plan.size() << "] p = (" << entry.point.transpose() << "), depth " << entry.depth
                << ", drag (" << entry.drag.transpose() << "): coarse " << r.coarseSeconds << " s, fine " << r.fineSeconds
                << " s, max |d| " << (r.fine - r.coarseOnFine).cwiseAbs().maxCoeff() << " m\n";
    }
    examples::saveExampleSet(set, output);
    std::cerr << "wrote " << set.examples.size() << " examples to " << output << "\n";
  } catch (const std::exception& e) {
    std::cerr << "de_make_examples: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
