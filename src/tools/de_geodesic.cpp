// de_geodesic: discrete geodesic between two shapes by temporal coarse-to-fine refinement, minimising the
// path energy (eq. 4) at every level, or with the smoothing flow (--flow; [Brandt16 §5-6]).
//   de_geodesic A.obj B.obj --shapes n --output DIR [--full | --subspace d] [--ghost N] [--flow] [--json]
// Writes DIR/geodesic_000.<ext> ... and prints {"length": L, "path_energy": E, "seconds": s, ...}.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <string>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/mesh_io.hpp"
#include "deformation_enrichment/seconds_since.hpp"
#include "deformation_enrichment/shape_space/blas_threads.hpp"
#include "deformation_enrichment/shape_space/discrete_shells.hpp"
#include "deformation_enrichment/shape_space/geodesic.hpp"
#include "deformation_enrichment/shape_space/shape_sequence.hpp"
#include "shape_space_cli.hpp"
#include "command_line.hpp"

namespace de = deformation_enrichment;
namespace ss = deformation_enrichment::shape_space;
namespace fs = std::filesystem;

int main(int argc, char** argv) {
  CLI::App app{"Shape-space geodesic between two shapes ([Brandt16])"};
  std::string pathA, pathB, output;
  int shapes = 8, insert = 2, rounds = 1;
  double tau = 1.0;
  bool useFlow = false;
  de::tools::ShapeSpaceCli common;  // no ghost mesh by default: 3 % longer on the finger
  app.add_option("A", pathA, "start shape (OBJ/PLY)")->required();
  app.add_option("B", pathB, "end shape, same topology")->required();
  app.add_option("--shapes", shapes, "shapes on the geodesic, ends included (>= 3)");
  app.add_option("--output", output, "output directory (created if missing)")->required();
  common.addTo(app, "reduced mode: ghost mesh vertices for the energy approximation (0 = off, the default: 3 % longer on the finger)",
               "symmetric averaging (eq. 1) instead of eq. 10 (--flow)");
  app.add_option("--insert", insert, "shapes inserted per segment and refinement level");
  app.add_option("--enrichment-rounds", rounds, "reduced mode: subspace enrichment rounds per level");
  app.add_flag("--flow", useFlow, "use the smoothing flow ([Brandt16]) instead of minimising eq. 4 directly");
  app.add_option("--tau", tau, "flow step size in (0, 1] (--flow)");
  if (const auto exitCode = deformation_enrichment::tools::parseCommandLine(app, argc, argv)) return *exitCode;
  ss::preferSingleThreadedBlas();

  try {
    const auto start = std::chrono::steady_clock::now();
    const de::mesh::TriangleMesh a = de::mesh::readTriangleMesh(pathA);
    const de::mesh::TriangleMesh b = de::mesh::readTriangleMesh(pathB);
    const ss::ShapeSequence ends = ss::makeSequence({a, b}, 2);
    const ss::DiscreteShells energy(ends.triangles, ends.numVertices(), common.parameters(ends.shapes.front()));
    ss::GeodesicOptions options;
    options.shapes = shapes;
    options.insertPerSegment = insert;
    options.tau = tau;
    common.applyTo(options.reduction);
    options.average.symmetric = common.symmetric;
    options.enrichmentRounds = rounds;
    options.solver = useFlow ? ss::GeodesicSolver::Flow : ss::GeodesicSolver::PathEnergy;
    std::cerr << "de_geodesic: " << ends.numVertices() << " vertices, " << shapes << " shapes, "
              << (common.full ? "full" : "reduced") << " space, " << (useFlow ? "flow" : "path energy") << "\n";
    const ss::GeodesicResult g = ss::geodesic(energy, ends.triangles, ends.shapes[0], ends.shapes[1], options);
    fs::create_directories(output);
    const std::string ext = fs::path(pathA).extension().string();
    for (size_t k = 0; k < g.shapes.size(); ++k) {
      char name[64];
      std::snprintf(name, sizeof(name), "geodesic_%03zu", k);
      de::mesh::writeTriangleMesh((fs::path(output) / (std::string(name) + ext)).string(),
                                  de::mesh::TriangleMesh{ss::unflatten(g.shapes[k]), ends.triangles});
    }
    const double seconds = de::secondsSince(start);
    std::cerr << "  length " << g.length << ", path energy " << g.pathEnergy << ", " << g.iterations
              << (useFlow ? " flow steps, " : " solver iterations, ") << "ghost vertices " << g.ghostVertices << ", "
              << seconds << " s\n";
    if (common.json) {
      nlohmann::json out;
      out["length"] = g.length;
      out["path_energy"] = g.pathEnergy;
      out["path_energy_history"] = g.pathEnergyHistory;
      out["iterations"] = g.iterations;
      out["evaluations"] = g.evaluations;
      out["ghost_vertices"] = g.ghostVertices;
      out["solver"] = useFlow ? "flow" : "path_energy";
      out["converged"] = g.converged;
      out["seconds"] = seconds;
      out["mode"] = common.full ? "full" : "reduced";
      std::cout << out.dump() << std::endl;
    }
    return 0;
  } catch (const de::Error& e) {
    std::cerr << "de_geodesic: " << e.what() << "\n";
    return 1;
  }
}
