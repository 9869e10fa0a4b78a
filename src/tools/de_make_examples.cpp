// de_make_examples: acquires an example set on the slab scene ([Seiler14 §3]). For every plan line it runs
// the coarse and the fine simulation, takes d = fine - coarse on the fine surface and stores descriptors
// and stamp. The set is rewritten after every example, so an interrupted run resumes where it stopped
// (examples already in SET with the same contact and pattern are kept, not recomputed).
#include <CLI/CLI.hpp>
#include <iostream>

#include "deformation_enrichment/acquisition/example_generation.hpp"
#include "deformation_enrichment/error.hpp"

using namespace deformation_enrichment;

int main(int argc, char** argv) {
  CLI::App app{"Acquire an example set (coarse vs fine simulations) for a scene"};
  std::string sceneName = "slab", output, planPath;
  int resolution = acquisition::SlabAcquisitionOptions().stampResolution;
  double toolRadius = acquisition::SlabAcquisitionOptions().toolRadius;
  std::vector<int> coarseCells{10, 10, 2}, fineCells{24, 24, 4};
  app.add_option("--scene", sceneName, "scene (slab)")->check(CLI::IsMember({"slab"}));
  app.add_option("--output", output, "example set directory ('default': the cache of the scene's default set)")->required();
  app.add_option("--plan", planPath, "CSV x,y,z,depth,dx,dy,dz per interaction (default: built-in slab plan)");
  app.add_option("--stamp-resolution", resolution, "stamp nodes per side");
  app.add_option("--coarse-cells", coarseCells, "coarse slab cells x y bulk-z (+1 skin layer)")->expected(3);
  app.add_option("--fine-cells", fineCells, "fine slab cells x y bulk-z (+2 skin layers)")->expected(3);
  app.add_option("--tool-radius", toolRadius, "tool footprint radius (m)");
  double stampRadius = acquisition::SlabAcquisitionOptions().enricher.stampRadius;
  app.add_option("--stamp-radius", stampRadius, "stamp radius R (m)")->check(CLI::PositiveNumber);
  double coarseSkinYoung = acquisition::SlabAcquisitionOptions().coarseSkinYoung;
  app.add_option("--coarse-skin-young", coarseSkinYoung, "skin Young's modulus of the coarse model (Pa; 0 = the fine one's)");
  double toolStiffness = acquisition::SlabAcquisitionOptions().toolStiffness;
  app.add_option("--tool-stiffness", toolStiffness, "penalty tool stiffness per area (Pa/m)")->check(CLI::PositiveNumber);
  std::string quadrature = "volume";
  app.add_option("--quadrature", quadrature, "descriptor quadrature: volume (lumped weights) or average (paper eq. 8)")
      ->check(CLI::IsMember({"volume", "average"}));
  std::string toolModel = "penalty";
  app.add_option("--tool-model", toolModel, "penalty (smooth footprint springs) or dirichlet (vertices under the tip)")
      ->check(CLI::IsMember({"penalty", "dirichlet"}));
  CLI11_PARSE(app, argc, argv);
  try {
    const std::vector<acquisition::PlanEntry> plan = planPath.empty() ? acquisition::defaultSlabPlan() : acquisition::readPlan(planPath);
    acquisition::SlabAcquisitionOptions options;
    options.stampResolution = resolution;
    options.toolRadius = toolRadius;
    options.coarseSkinYoung = coarseSkinYoung;
    options.toolStiffness = toolStiffness;
    options.enricher.descriptors.window.quadrature = descriptors::parseQuadrature(quadrature);
    options.enricher.stampRadius = stampRadius;
    options.toolModel = toolModel == "penalty" ? acquisition::ToolModel::Penalty : acquisition::ToolModel::Dirichlet;
    options.coarse.cells = Eigen::Vector3i(coarseCells[0], coarseCells[1], coarseCells[2]);
    options.fine.cells = Eigen::Vector3i(fineCells[0], fineCells[1], fineCells[2]);
    std::cerr << "building coarse and fine slabs, embedding and site sampling...\n";
    acquisition::SlabAcquisition acq(options);
    if (output == "default") output = acquisition::defaultExampleSetDirectory(sceneName);
    const examples::ExampleSet set = acq.acquireSet(plan, output, &std::cerr);
    std::cerr << "wrote " << set.examples.size() << " examples to " << output << "\n";
  } catch (const std::exception& e) {
    std::cerr << "de_make_examples: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
