// de_merge_examples: joins the sets of `de_make_examples --shard I/N` runs into one set, identical to a
// single run of the whole plan (examples in plan-line order, stamps bit for bit). Shards of different scenes
// or settings (provenance), shards without plan lines, or two shards holding the same plan line are refused
// before anything is written.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <iostream>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/examples/example_set_io.hpp"
#include "deformation_enrichment/scene_file/scene_description.hpp"
#include "command_line.hpp"

using namespace deformation_enrichment;

int main(int argc, char** argv) {
  CLI::App app{"Merge example-set shards (de_make_examples --shard) into one set"};
  std::string output;
  std::vector<std::string> shards;
  app.add_option("--output", output, "merged example set directory")->required();
  app.add_option("shards", shards, "shard directories")->required();
  if (const auto exitCode = deformation_enrichment::tools::parseCommandLine(app, argc, argv)) return *exitCode;
  try {
    examples::ExampleSet merged;
    std::string provenance;
    for (const std::string& path : shards) {
      examples::ExampleSet shard = examples::loadExampleSet(path);
      if (!shard.metadata.provenance) throw InvalidInputError(path + ": the set records no provenance (made before shards existed)");
      const std::string p = scene_file::sceneYaml(shard.metadata.provenance->scene);
      if (merged.examples.empty()) {
        merged.metadata = shard.metadata;
        provenance = p;
      } else if (p != provenance || shard.metadata.provenance->fileHashes != merged.metadata.provenance->fileHashes) {
        throw InvalidInputError(path + ": acquired on another scene or with other settings than " + shards.front() +
                                " (scene '" + shard.metadata.scene + "' vs '" + merged.metadata.scene + "')");
      }
      for (examples::Example& e : shard.examples) {
        if (e.planLine < 0) throw InvalidInputError(path + ": an example has no plan line");
        merged.examples.push_back(std::move(e));
      }
    }
    std::stable_sort(merged.examples.begin(), merged.examples.end(),
                     [](const examples::Example& a, const examples::Example& b) { return a.planLine < b.planLine; });
    for (std::size_t k = 1; k < merged.examples.size(); ++k)
      if (merged.examples[k].planLine == merged.examples[k - 1].planLine)
        throw InvalidInputError("plan line " + std::to_string(merged.examples[k].planLine + 1) + " is in two shards");
    examples::saveExampleSet(merged, output);
    std::cerr << "merged " << shards.size() << " shards, " << merged.examples.size() << " examples, into " << output << "\n";
  } catch (const std::exception& e) {
    std::cerr << "de_merge_examples: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
