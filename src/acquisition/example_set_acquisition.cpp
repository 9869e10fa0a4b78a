// The resumable, shardable acquisition loop of SceneAcquisition and the provenance a set records.
#include <sys/resource.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <ostream>
#include <sstream>
#include <vector>

#include "deformation_enrichment/acquisition/scene_acquisition.hpp"
#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/examples/example_set_io.hpp"

namespace deformation_enrichment::acquisition {
namespace {

namespace fs = std::filesystem;

std::string fileHash(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path + ": cannot read to record its hash");
  std::ostringstream bytes;
  bytes << in.rdbuf();
  const std::string data = bytes.str();
  char hex[17];
  std::snprintf(hex, sizeof(hex), "%016llx", static_cast<unsigned long long>(examples::fnv1a64(data.data(), data.size())));
  return hex;
}

double peakMegabytes() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024.0;  // Linux: kilobytes
}

bool sameInteraction(const examples::Example& e, std::size_t line, const ToolPath& path) {
  return e.planLine == static_cast<int>(line) && (e.contact - path.contact).norm() < 1e-9 &&
         std::abs(e.pattern.indentDepth - path.depth) < 1e-12 && (e.pattern.drag - path.drag).norm() < 1e-12;
}

}  // namespace

examples::Provenance provenanceOf(const scene_file::SceneDescription& scene, const RecordedCoarse* coarse) {
  examples::Provenance p;
  if (coarse) {
    p.fileHashes[fs::path(coarse->path).filename().string()] = fileHash(coarse->path);
    p.coarseSimulator = coarse->simulator;
  }
  p.scene = scene;
  std::vector<std::string> files{scene.surface, scene.volume, scene.plan == "auto" ? "" : scene.plan};
  if (fs::path(scene.volume).extension() == ".node") files.push_back(fs::path(scene.volume).replace_extension(".ele").string());
  for (const std::string& file : files)
    if (!file.empty()) p.fileHashes[fs::path(file).filename().string()] = fileHash(file);
  return p;
}

examples::ExampleSet SceneAcquisition::acquireSet(const std::vector<PlanEntry>& plan, const std::string& directory,
                                                  std::ostream* log, const Shard& shard, const RecordedCoarse* coarse) {
  if (shard.count < 1 || shard.index < 1 || shard.index > shard.count)
    throw InvalidInputError("acquireSet: shard " + std::to_string(shard.index) + "/" + std::to_string(shard.count) +
                            " is not I/N with 1 <= I <= N");
  examples::ExampleSet set;
  set.metadata.scene = scene_.name;
  set.metadata.provenance = provenanceOf(scene_, coarse);
  set.metadata.description = coarse ? "de_make_examples: " + coarse->simulator + "'s coarse states recorded in " +
                                          fs::path(coarse->path).filename().string() + " vs fine Stable Neo-Hookean solves on scene '" +
                                          scene_.name + "'"
                                    : "de_make_examples: coarse vs fine Stable Neo-Hookean solves on scene '" + scene_.name + "'";
  examples::ExampleSet previous;
  if (fs::exists(fs::path(directory) / examples::kManifestFile)) {
    try {
      previous = examples::loadExampleSet(directory);
      // A manifest without stamp_layers reads back with the default layers in its provenance.
      const bool sameStamps = !previous.examples.empty() && previous.examples.front().stampLayers == scene_.stamp.layers;
      const bool same = sameStamps && previous.metadata.provenance &&
                        scene_file::sceneYaml(previous.metadata.provenance->scene) == scene_file::sceneYaml(scene_) &&
                        previous.metadata.provenance->fileHashes == set.metadata.provenance->fileHashes &&
                        previous.metadata.provenance->coarseSimulator == set.metadata.provenance->coarseSimulator;
      if (!same) previous.examples.clear();
      if (log) *log << (same ? "resuming: " + std::to_string(previous.examples.size()) + " examples already in " + directory
                             : "the set in " + directory + " was made with another scene or settings: starting over")
                    << "\n";
    } catch (const Error& e) {
      if (log) *log << "existing set not reusable (" << e.what() << "), starting over\n";
    }
  }
  // Every line of the shard is checked before anything is simulated or written: bad input leaves an existing
  // set untouched.
  std::vector<std::size_t> lines;
  std::vector<ToolPath> paths;
  for (std::size_t line = 0; line < plan.size(); ++line) {
    if (!shard.holds(line)) continue;
    if (coarse && !coarse->settled.count(line)) {
      if (log) *log << "plan line " << line + 1 << ": no settled coarse state in " << coarse->path << ", left out\n";
      continue;
    }
    try {
      paths.push_back(toolPath(plan[line]));
    } catch (const InvalidInputError& e) {
      throw InvalidInputError("plan line " + std::to_string(line + 1) + ": " + e.what());
    }
    lines.push_back(line);
  }
  if (lines.empty())
    throw InvalidInputError("acquireSet: shard " + std::to_string(shard.index) + "/" + std::to_string(shard.count) +
                            " holds no line of a " + std::to_string(plan.size()) + "-line plan");
  const std::size_t todo = lines.size();
  for (std::size_t k = 0; k < todo; ++k) {
    const std::size_t line = lines[k], done = k + 1;
    const ToolPath& path = paths[k];
    const auto kept = std::find_if(previous.examples.begin(), previous.examples.end(),
                                   [&](const examples::Example& e) { return sameInteraction(e, line, path); });
    if (kept != previous.examples.end()) {
      set.examples.push_back(*kept);
      if (log) *log << "[" << done << "/" << todo << "] plan line " << line + 1 << " already acquired, kept\n";
      continue;
    }
    const InteractionResult r = coarse ? simulate(plan[line], coarse->settled.at(line)) : simulate(plan[line]);
    if (!r.converged && log) *log << "  warning: " << r.message << "\n";
    set.examples.push_back(makeExample(plan[line], r));
    set.examples.back().planLine = static_cast<int>(line);
    examples::saveExampleSet(set, directory);  // after every example: resumable
    if (log)
      *log << "[" << done << "/" << todo << "] plan line " << line + 1 << ": p = (" << path.contact.transpose() << "), depth "
           << path.depth << ": coarse " << r.coarseSeconds << " s, fine " << r.fineSeconds << " s, max |d| "
           << (r.fine - r.coarseOnFine).cwiseAbs().maxCoeff() << " m, peak memory " << peakMegabytes() << " MB" << std::endl;
  }
  examples::saveExampleSet(set, directory);
  return set;
}

std::string defaultExampleSetDirectory(const std::string& scene) {
  if (const char* cache = std::getenv("DE_EXAMPLE_CACHE"); cache && *cache) return (fs::path(cache) / scene).string();
  fs::path base;
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg) {
    base = xdg;
  } else if (const char* home = std::getenv("HOME"); home && *home) {
    base = fs::path(home) / ".cache";
  } else {
    throw IoError("defaultExampleSetDirectory: neither DE_EXAMPLE_CACHE, XDG_CACHE_HOME nor HOME is set");
  }
  return (base / "deformation_enrichment" / "example_sets" / scene).string();
}

}  // namespace deformation_enrichment::acquisition
