// de_fine_convergence: is a scene's fine model converged? Solves random held-out interactions with the
// fine model at several tet counts (--levels 1,2,4: factors over the scene's own) and prints JSON: per
// level the tets and solve time, per interaction the RMS change of the fine solution between consecutive
// levels over the display vertices within the stamp radius, and that change as a fraction of the coarse
// model's error there (acquisition/fine_convergence.hpp). Progress on stderr; exit 1 with a message on bad input.
#include <CLI/CLI.hpp>
#include <cmath>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "deformation_enrichment/acquisition/fine_convergence.hpp"
#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/number_parsing.hpp"
#include "command_line.hpp"

using namespace deformation_enrichment;
using nlohmann::json;

namespace {

std::vector<double> parseLevels(const std::string& text) {
  std::vector<double> levels;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    const std::optional<double> factor = parseReal(item);
    if (!factor || !(*factor >= 1.0 && std::isfinite(*factor))) throw InvalidInputError("--levels: '" + item + "' is not a factor >= 1");
    levels.push_back(*factor);
  }
  return levels;  // fineConvergence checks the order and the leading 1
}

json toJson(const acquisition::FineConvergence& c, const std::string& scene, int count, unsigned seed) {
  json out;
  out["scene"] = scene;
  out["held_out"] = count;
  out["seed"] = seed;
  for (const auto& l : c.levels)
    out["levels"].push_back({{"factor", l.factor}, {"fine_nodes", l.fineNodes}, {"fine_tets", l.fineTets}, {"fine_seconds", l.seconds}});
  for (const auto& k : c.contacts)
    out["contacts"].push_back({{"vertices", k.vertices}, {"coarse_rms_m", k.coarseRms}, {"change_rms_m", k.changeRms}});
  for (std::size_t pair = 0; pair + 1 < c.levels.size(); ++pair)
    out["changes"].push_back({{"from", c.levels[pair].factor},
                              {"to", c.levels[pair + 1].factor},
                              {"mean_of_coarse_error", c.meanRelativeChange(pair)},
                              {"worst_of_coarse_error", c.worstRelativeChange(pair)}});
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Convergence of a scene's fine model: the held-out truth at several fine tet counts"};
  std::string scene, levels = "1,2,4";
  int count = 8;
  unsigned seed = 1;
  app.add_option("--scene", scene, "shipped scene name or scene file (.yaml)")->required();
  app.add_option("--levels", levels, "tet-count factors over the scene's fine model, ascending from 1")->capture_default_str();
  app.add_option("--held-out", count, "random held-out interactions")->check(CLI::PositiveNumber)->capture_default_str();
  app.add_option("--seed", seed, "seed of the random held-out interactions")->capture_default_str();
  if (const auto exitCode = deformation_enrichment::tools::parseCommandLine(app, argc, argv)) return *exitCode;
  try {
    const scene_file::SceneDescription description = scene_file::readSceneFile(scene_file::findSceneFile(scene));
    std::cerr << "held-out contacts: " << count << " random, seed " << seed << "\n";
    const acquisition::FineConvergence c =
        acquisition::fineConvergence(description, parseLevels(levels), count, seed, [](const std::string& line) { std::cerr << line << "\n"; });
    std::cout << toJson(c, description.name, count, seed).dump(2) << std::endl;
  } catch (const std::exception& e) {
    std::cerr << "de_fine_convergence: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
