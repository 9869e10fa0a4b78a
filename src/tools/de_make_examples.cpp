// de_make_examples: acquires an example set on a scene ([Seiler14 §3]; scene files: docs/scenes.md). For
// every plan line it runs the coarse and the fine simulation, takes d = fine - coarse on the display surface
// and stores descriptors and stamp. The set is rewritten after every example, so an interrupted run resumes
// where it stopped; --shard I/N acquires every N-th plan line starting at line I, for parallel jobs whose
// sets de_merge_examples joins. Bad input (scene, plan, flags) is refused before anything is written.
#include <CLI/CLI.hpp>
#include <chrono>
#include <iostream>
#include <regex>

#include "deformation_enrichment/acquisition/plan_generation.hpp"
#include "deformation_enrichment/acquisition/scene_acquisition.hpp"
#include "deformation_enrichment/error.hpp"
#ifdef DE_COARSE_BAG
#include "deformation_enrichment/ros/coarse_bag.hpp"
#include "deformation_enrichment/seconds_since.hpp"
#endif
#include "command_line.hpp"

using namespace deformation_enrichment;

namespace {

acquisition::Shard parseShard(const std::string& text) {
  std::smatch m;
  if (!std::regex_match(text, m, std::regex("([0-9]{1,6})/([0-9]{1,6})")))
    throw InvalidInputError("--shard must be I/N, e.g. 2/8, got '" + text + "'");
  acquisition::Shard shard{std::stoi(m[1]), std::stoi(m[2])};
  if (shard.count < 1 || shard.index < 1 || shard.index > shard.count)
    throw InvalidInputError("--shard I/N needs 1 <= I <= N, got " + text);
  return shard;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Acquire an example set (coarse vs fine Stable Neo-Hookean simulations) on a scene"};
  std::string sceneName = "slab", output, planPath, shardText = "1/1";
  std::optional<int> examples;
  app.add_option("--scene", sceneName, "shipped scene name or scene file (.yaml)");
  app.add_option("--output", output, "example set directory ('default': the cache of the scene's default set)")->required();
  app.add_option("--plan", planPath, "CSV x,y,z,depth,dx,dy,dz per interaction (default: the scene's plan)");
  app.add_option("--examples", examples,
                 "the first N interactions of the plan: of --plan when given, else of the scene's nested automatic plan "
                 "(default: the scene's plan; an automatic one has 12)")
      ->check(CLI::PositiveNumber);
  std::string coarseBag;
#ifdef DE_COARSE_BAG
  app.add_option("--coarse-bag", coarseBag, "recording of another coarse simulator (docs/coarse_simulator.md): acquisition_driver's "
                 "(its plan) or a session of servo_cp and mesh_state (the plan from --plan); its settled states are the coarse half")
      ->check(CLI::ExistingFile);
#endif
  app.add_option("--shard", shardText, "acquire every N-th plan line starting at line I (I/N, 1-based)");
  // Overrides of the scene file, for experiments; recorded in the set's provenance like the file's values.
  std::optional<int> resolution, layers;
  std::optional<double> stampRadius, toolRadius, toolStiffness, coarseSkinYoung;
  std::optional<std::string> quadrature, toolModel;
  app.add_option("--stamp-resolution", resolution, "stamp nodes per side")->check(CLI::Range(2, 4096));
  app.add_option("--stamp-layers", layers, "stamp layers along the normal (1: the paper's surface stamp)")->check(CLI::Range(1, 64));
  app.add_option("--stamp-radius", stampRadius, "stamp radius R (m)")->check(CLI::PositiveNumber);
  app.add_option("--tool-radius", toolRadius, "tool footprint radius (m)")->check(CLI::PositiveNumber);
  app.add_option("--tool-stiffness", toolStiffness, "penalty tool stiffness per area (Pa/m)")->check(CLI::PositiveNumber);
  app.add_option("--coarse-skin-young", coarseSkinYoung, "skin Young's modulus of the coarse model (Pa)")->check(CLI::PositiveNumber);
  app.add_option("--quadrature", quadrature, "descriptor quadrature: volume or average ([Seiler14 eq. 8])")
      ->check(CLI::IsMember({"volume", "average"}));
  app.add_option("--tool-model", toolModel, "penalty (smooth footprint springs) or dirichlet (vertices under the tip)")
      ->check(CLI::IsMember({"penalty", "dirichlet"}));
  if (const auto exitCode = deformation_enrichment::tools::parseCommandLine(app, argc, argv)) return *exitCode;
  try {
    const auto start = std::chrono::steady_clock::now();
    const acquisition::Shard shard = parseShard(shardText);
    scene_file::SceneDescription scene = scene_file::readSceneFile(scene_file::findSceneFile(sceneName));
    if (resolution) scene.stamp.resolution = *resolution;
    if (layers) scene.stamp.layers = *layers;
    if (stampRadius) scene.stamp.radius = *stampRadius;
    if (toolRadius) scene.tool.radius = *toolRadius;
    if (toolStiffness) scene.tool.stiffness = *toolStiffness;
    if (coarseSkinYoung) {
      if (!scene.skin) throw InvalidInputError("--coarse-skin-young: scene '" + scene.name + "' has no skin");
      scene.coarseSkinYoung = *coarseSkinYoung;
    }
    if (quadrature) scene.descriptors.averageQuadrature = *quadrature == "average";
    if (toolModel) scene.tool.model = *toolModel == "penalty" ? scene_file::ToolModel::Penalty : scene_file::ToolModel::Dirichlet;
    if (!planPath.empty()) scene.plan = planPath;
    else if (examples) scene.plan = "auto";  // the nested plan, on every scene
    std::cerr << "scene " << scene.name << " (" << scene.path << "): building the coarse and fine models...\n";
    acquisition::SceneAcquisition acq(scene);
    std::cerr << acq.models().report << "\n";
    const auto [outside, farthest] = acq.outsideVertices();
    if (outside > 0)
      std::cerr << outside << " display vertices lie outside the coarse volume (up to " << farthest * 1e3
                << " mm): their coarse motion is extrapolated from the nearest tet\n";
    std::optional<acquisition::RecordedCoarse> recorded;
#ifdef DE_COARSE_BAG
    if (!coarseBag.empty()) {
      if (examples) throw InvalidInputError("--coarse-bag brings its plan, or takes one with --plan: no --examples with it");
      // The driver's bag names its plan; a session recorded with the user's own tools takes it from --plan.
      recorded = planPath.empty() ? ros_layer::readCoarseBag(coarseBag, acq.fineSurface().numVertices())
                                  : ros_layer::readSessionBag(coarseBag, acq, acquisition::readPlan(planPath));
      std::cerr << "coarse half: " << recorded->settled.size() << " of " << recorded->plan.size() << " interactions recorded from "
                << recorded->simulator << " in " << coarseBag << "\n";
    }
#endif
    const std::vector<acquisition::PlanEntry> plan = recorded ? recorded->plan : acquisition::scenePlan(acq, examples);
    if (output == "default") output = acquisition::defaultExampleSetDirectory(scene.name);
    const examples::ExampleSet set = acq.acquireSet(plan, output, &std::cerr, shard, recorded ? &*recorded : nullptr);
    const double seconds = secondsSince(start);
    std::cerr << "wrote " << set.examples.size() << " examples (shard " << shard.index << "/" << shard.count << " of a "
              << plan.size() << "-line plan) to " << output << " in " << seconds << " s\n";
  } catch (const std::exception& e) {
    std::cerr << "de_make_examples: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
