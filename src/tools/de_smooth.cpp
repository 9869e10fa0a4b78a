// de_smooth: smooths a deformation sequence with the shape-space flow of [Brandt16] (eq. 2 with step
// control, optional restoring force), reduced (PCA subspace + BFGS) or full space (Newton).
//   de_smooth --input F0.obj F1.obj ... --output DIR --iterations K --tau T --restoring R [--closed]
//             [--subspace d | --full] [--ghost N] [--json]
//   de_smooth --input clip.md2 --frames A:B --output DIR ...   (an MD2 animation's frames A..B-1)
// Writes the smoothed shapes under the same file names in DIR (OBJ or PLY, by extension; an MD2 clip's
// frames as NNN_<frame name>.obj) and prints one
// JSON object {"path_energy": [input, after step 1, ...], "seconds": s, "status": ..., ...}; progress goes to
// stderr. path_energy is eq. 4 on the full mesh; with a ghost mesh, ghost_path_energy is the one the step
// control lowers. A step that no tau lets lower eq. 4 ends the run (stalled); a step whose averages did not
// all converge is kept and reported (unconverged_averages, unconverged_gradient_norm). Exit status 0 if a
// step was accepted (or none was asked for), 3 if none was (the input is written unchanged), 1 on errors.
#include <chrono>
#include <filesystem>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/md2_reader.hpp"
#include "deformation_enrichment/mesh/mesh_io.hpp"
#include "deformation_enrichment/number_parsing.hpp"
#include "deformation_enrichment/seconds_since.hpp"
#include "deformation_enrichment/shape_space/blas_threads.hpp"
#include "deformation_enrichment/shape_space/discrete_shells.hpp"
#include "deformation_enrichment/shape_space/smoothing_flow.hpp"
#include "shape_space_cli.hpp"
#include "command_line.hpp"

namespace de = deformation_enrichment;
namespace ss = deformation_enrichment::shape_space;
namespace fs = std::filesystem;

namespace {

struct Inputs {
  std::vector<de::mesh::TriangleMesh> meshes;
  std::vector<std::string> names;  ///< output file names
};

// "A:B" (0-based, B exclusive) of a clip with `count` frames; an empty text is every frame.
std::pair<std::size_t, std::size_t> frameRange(const std::string& text, std::size_t count) {
  if (text.empty()) return {0, count};
  const auto colon = text.find(':');
  const std::optional<long> a = colon == std::string::npos ? std::nullopt : de::parseInteger(text.substr(0, colon));
  const std::optional<long> b = colon == std::string::npos ? std::nullopt : de::parseInteger(text.substr(colon + 1));
  if (!a || !b) throw de::InvalidInputError("--frames: '" + text + "' is not A:B (0-based, B exclusive)");
  if (!(*a >= 0 && *a < *b && static_cast<std::size_t>(*b) <= count))
    throw de::InvalidInputError("--frames " + text + ": needs 0 <= A < B <= " + std::to_string(count) + " (the clip's frames)");
  return {static_cast<std::size_t>(*a), static_cast<std::size_t>(*b)};
}

// Mesh files as they are, or the frames of one MD2 animation (assimp-testmodels' faerie.md2, ...).
Inputs readInputs(const std::vector<std::string>& paths, const std::string& frames) {
  Inputs in;
  const bool md2 = paths.size() == 1 && fs::path(paths[0]).extension() == ".md2";
  if (!md2) {
    if (!frames.empty()) throw de::InvalidInputError("--frames selects frames of one .md2 animation");
    for (const std::string& path : paths) {
      in.meshes.push_back(de::mesh::readTriangleMesh(path));
      in.names.push_back(fs::path(path).filename().string());
    }
    return in;
  }
  de::mesh::Md2Animation clip = de::mesh::readMd2(paths[0]);
  const auto [first, end] = frameRange(frames, clip.frames.size());
  for (std::size_t f = first; f < end; ++f) {
    std::string index = std::to_string(f);
    index.insert(0, index.size() < 3 ? 3 - index.size() : 0, '0');
    in.meshes.push_back(std::move(clip.frames[f]));
    in.names.push_back(index + "_" + clip.frameNames[f] + ".obj");
  }
  return in;
}

// Up to `iterations` flow steps (a stalled one ends the run), reported on stderr and as the JSON summary's
// per-step arrays and status.
nlohmann::json run(ss::SmoothingFlow& flow, int iterations) {
  const bool ghost = flow.ghostVertices() > 0;
  nlohmann::json out, energies = nlohmann::json::array(), ghostEnergies = nlohmann::json::array();
  nlohmann::json taus = nlohmann::json::array(), solverIterations = nlohmann::json::array();
  nlohmann::json unconverged = nlohmann::json::array(), unconvergedNorms = nlohmann::json::array();
  energies.push_back(flow.pathEnergy());
  if (ghost) ghostEnergies.push_back(flow.controlledPathEnergy());
  int accepted = 0;
  bool allConverged = true, stalled = false;
  for (int k = 0; k < iterations; ++k) {
    const ss::FlowStep step = flow.step();
    if ((stalled = step.stalled)) {
      std::cerr << "  step " << k + 1 << ": stalled (no tau lowers the path energy), the run ends here\n";
      break;
    }
    ++accepted;
    allConverged = allConverged && step.converged();
    energies.push_back(ghost ? flow.pathEnergy() : step.pathEnergy);
    if (ghost) ghostEnergies.push_back(step.pathEnergy);
    taus.push_back(step.tau);
    solverIterations.push_back(step.solverIterations);
    unconverged.push_back(step.unconvergedAverages);
    unconvergedNorms.push_back(step.unconvergedGradientNorm);
    std::cerr << "  step " << k + 1 << ": path energy " << energies.back().get<double>() << " tau " << step.tau;
    if (step.unconvergedAverages > 0)
      std::cerr << " (" << step.unconvergedAverages << " averages not converged, gradient norm up to "
                << step.unconvergedGradientNorm << ")";
    std::cerr << "\n";
  }
  out["path_energy"] = energies;
  if (ghost) out["ghost_path_energy"] = ghostEnergies;
  out["ghost_vertices"] = flow.ghostVertices();
  out["subspace_dimension"] = flow.subspaceDimension();
  out["tau"] = taus;
  out["solver_iterations"] = solverIterations;
  out["unconverged_averages"] = unconverged;
  out["unconverged_gradient_norm"] = unconvergedNorms;
  out["accepted_steps"] = accepted;
  out["stalled"] = stalled;
  out["status"] = accepted == 0 && iterations > 0 ? "nothing_accepted" : allConverged ? "converged" : "not_converged";
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Shape-space smoothing flow for deformation sequences ([Brandt16])"};
  std::vector<std::string> inputs;
  std::string output, frames;
  int iterations = 10;
  double tau = 0.5, restoring = 0.0;
  bool closed = false, proportional = false;
  de::tools::ShapeSpaceCli common;
  common.ghost = 1250;
  common.subspace = ss::kSmoothingSubspaceDimension;
  std::vector<int> restoredShapes;
  app.add_option("--input", inputs, "input meshes (OBJ/PLY, same topology) in temporal order, or one MD2 animation")->required();
  app.add_option("--frames", frames, "A:B: the MD2 animation's frames A..B-1 (0-based; default: all)");
  app.add_option("--output", output, "output directory (created if missing)")->required();
  app.add_option("--iterations", iterations, "flow steps")->check(CLI::NonNegativeNumber);
  app.add_option("--tau", tau, "step size in (0, 1]");
  app.add_option("--restoring", restoring, "restoring force rho in [0, 1)");
  app.add_option("--restore-shapes", restoredShapes, "indices of the shapes that feel rho (default: all)");
  app.add_flag("--closed", closed, "periodic sequence");
  common.addTo(app, "reduced mode: ghost mesh vertices for the energy approximation (0 = off)",
               "symmetric averaging (eq. 1) instead of eq. 10");
  app.add_flag("--proportional", proportional, "proportion-preserving weights");
  if (const auto exitCode = deformation_enrichment::tools::parseCommandLine(app, argc, argv)) return *exitCode;
  ss::preferSingleThreadedBlas();

  try {
    const auto start = std::chrono::steady_clock::now();
    const Inputs in = readInputs(inputs, frames);
    const ss::ShapeSequence sequence = ss::makeSequence(in.meshes);
    const ss::DiscreteShells energy(sequence.triangles, sequence.numVertices(), common.parameters(sequence.shapes.front()));
    ss::FlowOptions options;
    options.tau = tau;
    options.rho = restoring;
    options.restoredShapes = restoredShapes;
    options.closed = closed;
    common.applyTo(options.reduction);
    options.symmetricAverage = common.symmetric;
    options.weights = proportional ? ss::FlowWeights::ProportionPreserving : ss::FlowWeights::Fixed;
    options.parallelShapes = true;  // DiscreteShells is thread-safe; the Jacobi update makes shapes independent
    ss::SmoothingFlow flow(energy, sequence, options);
    std::cerr << "de_smooth: " << in.meshes.size() << " shapes, " << sequence.numVertices() << " vertices, path energy "
              << flow.pathEnergy() << "\n";
    nlohmann::json out = run(flow, iterations);
    const int accepted = out["accepted_steps"].get<int>();
    fs::create_directories(output);
    for (size_t i = 0; i < in.meshes.size(); ++i)
      de::mesh::writeTriangleMesh((fs::path(output) / in.names[i]).string(), ss::shapeMesh(flow.current(), Eigen::Index(i)));
    const double seconds = de::secondsSince(start);
    if (common.json) {
      out["seconds"] = seconds;
      out["shapes"] = in.meshes.size();
      out["vertices"] = sequence.numVertices();
      out["mode"] = common.full ? "full" : "reduced";
      std::cout << out.dump() << std::endl;
    }
    if (accepted == 0 && iterations > 0) {
      std::cerr << "de_smooth: no step was accepted (no tau lowers the path energy); the input was written unchanged\n";
      return 3;
    }
    return 0;
  } catch (const de::Error& e) {
    std::cerr << "de_smooth: " << e.what() << "\n";
    return 1;
  }
}
