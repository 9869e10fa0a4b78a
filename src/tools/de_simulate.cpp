// de_simulate: runs a procedural (or TetGen) scene under a tool that indents and optionally drags
// laterally, solving each step to quasi-static equilibrium with the Stable Neo-Hookean FEM. Writes the
// surface of every step as OBJ and a JSON log of Newton iterations, residuals and times; progress on stderr.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <nlohmann/json.hpp>

#include "deformation_enrichment/elasticity/quasi_static_solver.hpp"
#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/tet_surface.hpp"
#include "deformation_enrichment/mesh/tetgen_io.hpp"
#include "deformation_enrichment/scenes/procedural_scene.hpp"
#include "deformation_enrichment/acquisition/tool_loading.hpp"

using namespace deformation_enrichment;
using nlohmann::json;

namespace {

void writeObj(const std::string& path, const mesh::TetSurface& surface, const Eigen::Matrix3Xd& positions) {
  std::ofstream out(path);
  if (!out) throw IoError("cannot write " + path);
  out << std::setprecision(9);
  for (int v : surface.surfaceToVolume)
    out << "v " << positions(0, v) << ' ' << positions(1, v) << ' ' << positions(2, v) << '\n';
  for (Eigen::Index f = 0; f < surface.surface.numTriangles(); ++f)
    out << "f " << surface.surface.triangles(0, f) + 1 << ' ' << surface.surface.triangles(1, f) + 1 << ' '
        << surface.surface.triangles(2, f) + 1 << '\n';
  if (!out) throw IoError("failed while writing " + path);
}

/// TetGen mesh as a scene: region ids become material ids (clamped to bulk/skin), vertices at the lowest
/// z (within `tolerance`) are the support, the highest-z layer (within `tolerance`) the top.
scenes::Scene sceneFromTetGen(const std::string& base, double tolerance) {
  const mesh::TetGenMesh read = mesh::readTetGen(base);
  scenes::Scene scene;
  scene.name = base;
  scene.mesh = read.mesh;
  scene.materialId = read.region.cwiseMax(0).cwiseMin(1);
  const double bottom = scene.mesh.vertices.row(2).minCoeff(), top = scene.mesh.vertices.row(2).maxCoeff();
  for (Eigen::Index v = 0; v < scene.mesh.numVertices(); ++v) {
    if (scene.mesh.vertices(2, v) <= bottom + tolerance) scene.fixedVertices.push_back(static_cast<int>(v));
    if (scene.mesh.vertices(2, v) >= top - tolerance) scene.topVertices.push_back(static_cast<int>(v));
  }
  return scene;
}

json toJson(const Eigen::Vector3d& v) { return json::array({v.x(), v.y(), v.z()}); }

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Quasi-static Stable Neo-Hookean simulation of a tool indenting / dragging a soft-tissue scene"};
  std::string sceneName = "slab", tetgenBase, outDir = "de_simulate_out", variantName = "paper", solverName = "auto";
  std::string mode = "indent";
  std::vector<int> cells;
  double skinThickness = 0.0, bulkYoung = 1e4, bulkPoisson = 0.45, skinYoung = 1e6, skinPoisson = 0.3;
  int skinLayers = 0, steps = 10, indentSteps = 4, maxIterations = 100;
  std::vector<double> point{0.0, 0.0}, indentDirection{0.0, 0.0, -1.0}, dragDirection{1.0, 0.0, 0.0};
  double toolRadius = 0.004, depth = 0.004, dragDistance = 0.01, tolerance = 1e-8, maxSeconds = 600.0, fixTolerance = 1e-6;
  app.add_option("--scene", sceneName, "slab | pillow | meniscus")->check(CLI::IsMember({"slab", "pillow", "meniscus"}));
  app.add_option("--tetgen", tetgenBase, "read <base>.node/.ele instead (lowest z fixed, highest z is the top)");
  app.add_option("--fix-tolerance", fixTolerance, "TetGen scenes: z tolerance of the support and top layers (m)");
  app.add_option("--cells", cells, "cells: first, second surface direction, bulk thickness (3 integers)")->expected(3);
  auto* skinThicknessOption = app.add_option("--skin-thickness", skinThickness, "skin thickness in m (0 = no skin; default: the scene's)");
  auto* skinLayersOption = app.add_option("--skin-layers", skinLayers, "cell layers through the skin (default: the scene's)");
  app.add_option("--bulk-young", bulkYoung, "bulk Young's modulus (Pa)");
  app.add_option("--bulk-poisson", bulkPoisson, "bulk Poisson ratio");
  app.add_option("--skin-young", skinYoung, "skin Young's modulus (Pa)");
  app.add_option("--skin-poisson", skinPoisson, "skin Poisson ratio");
  app.add_option("--variant", variantName, "paper | production")->check(CLI::IsMember({"paper", "production"}));
  app.add_option("--mode", mode, "indent | drag")->check(CLI::IsMember({"indent", "drag"}));
  app.add_option("--point", point, "tool position x y on the top surface (m)")->expected(2);
  app.add_option("--tool-radius", toolRadius, "tool footprint radius (m)");
  app.add_option("--depth", depth, "indentation depth (m)");
  app.add_option("--indent-direction", indentDirection, "indentation direction (3 numbers)")->expected(3);
  app.add_option("--direction", dragDirection, "drag direction (3 numbers)")->expected(3);
  app.add_option("--drag-distance", dragDistance, "drag distance (m)");
  app.add_option("--steps", steps, "steps of the motion (indent mode: indentation steps; drag mode: drag steps)");
  app.add_option("--indent-steps", indentSteps, "drag mode: indentation steps before the drag");
  app.add_option("--solver", solverName, "auto | cholmod | ldlt")->check(CLI::IsMember({"auto", "cholmod", "ldlt"}));
  app.add_option("--max-iterations", maxIterations, "Newton iterations per step");
  app.add_option("--tolerance", tolerance, "relative force tolerance");
  app.add_option("--max-seconds", maxSeconds, "time limit per step (s)");
  double exactBelow = elasticity::SolverSettings().exactHessianBelow;
  double reuseContraction = elasticity::SolverSettings().reuseContraction;
  app.add_option("--exact-below", exactBelow, "try the exact Hessian once |f| <= this fraction of |f_0| (0 = never)");
  app.add_option("--reuse-contraction", reuseContraction, "reuse a factorisation after a step shrinking |f| to this fraction (0 = never)");
  app.add_option("--out", outDir, "output directory (OBJ per step, log.json)");
  CLI11_PARSE(app, argc, argv);

  try {
    scenes::Scene scene;
    if (!tetgenBase.empty()) {
      scene = sceneFromTetGen(tetgenBase, fixTolerance);
    } else {
      scenes::Layering layering;
      if (sceneName == "meniscus") layering = scenes::MeniscusOptions().layering;
      if (!cells.empty()) layering.cells = Eigen::Vector3i(cells[0], cells[1], cells[2]);
      if (skinThicknessOption->count()) layering.skinThickness = skinThickness;
      if (skinLayersOption->count()) layering.skinLayers = skinLayers;
      if (sceneName == "slab") {
        scenes::SlabOptions options;
        options.layering = layering;
        scene = scenes::makeSlab(options);
      } else if (sceneName == "pillow") {
        scenes::PillowOptions options;
        options.layering = layering;
        scene = scenes::makePillow(options);
      } else {
        scenes::MeniscusOptions options;
        options.layering = layering;
        scene = scenes::makeMeniscus(options);
      }
    }
    const elasticity::SnhVariant variant = variantName == "paper" ? elasticity::SnhVariant::Paper : elasticity::SnhVariant::Production;
    const auto bulk = elasticity::lameFromYoungPoisson(bulkYoung, bulkPoisson);
    const auto skin = elasticity::lameFromYoungPoisson(skinYoung, skinPoisson);
    const elasticity::TetFem fem(scene.mesh,
                                 {elasticity::StableNeoHookean(bulk.mu, bulk.lambda, variant),
                                  elasticity::StableNeoHookean(skin.mu, skin.lambda, variant)},
                                 scene.materialId);
    elasticity::SolverSettings settings;
    settings.maxIterations = maxIterations;
    settings.relativeForceTolerance = tolerance;
    settings.maxSeconds = maxSeconds;
    settings.exactHessianBelow = exactBelow;
    settings.reuseContraction = reuseContraction;
    settings.linearSolver = solverName == "cholmod" ? elasticity::LinearSolverKind::Cholmod
                            : solverName == "ldlt"  ? elasticity::LinearSolverKind::SimplicialLDLT
                                                    : elasticity::LinearSolverKind::Auto;
    elasticity::QuasiStaticSolver solver(fem, settings);
    const std::vector<int> tool = acquisition::toolFootprint(scene, Eigen::Vector2d(point[0], point[1]), toolRadius);
    const mesh::TetSurface surface = mesh::extractSurface(scene.mesh);
    std::filesystem::create_directories(outDir);

    const bool drag = mode == "drag";
    const int firstPhase = drag ? indentSteps : steps;
    const int dragSteps = drag ? steps : 0;
    const Eigen::Vector3d indent(indentDirection[0], indentDirection[1], indentDirection[2]);
    const Eigen::Vector3d along(dragDirection[0], dragDirection[1], dragDirection[2]);
    std::cerr << "scene " << scene.name << ": " << scene.mesh.numVertices() << " vertices, " << scene.mesh.numTets()
              << " tets, " << tool.size() << " tool vertices, " << scene.fixedVertices.size() << " support vertices\n";
    json log;
    log["scene"] = {{"name", scene.name}, {"vertices", scene.mesh.numVertices()}, {"tets", scene.mesh.numTets()},
                    {"tool_vertices", tool.size()}, {"support_vertices", scene.fixedVertices.size()}};
    log["settings"] = {{"mode", mode}, {"variant", variantName}, {"solver", solverName}, {"depth", depth},
                       {"drag_distance", dragDistance}, {"tool_radius", toolRadius}, {"tolerance", tolerance}};
    log["steps"] = json::array();
    Eigen::Matrix3Xd positions = scene.mesh.vertices;
    writeObj(outDir + "/step_000.obj", surface, positions);
    bool allConverged = true;
    for (int step = 1; step <= firstPhase + dragSteps; ++step) {
      const Eigen::Vector3d displacement = acquisition::toolDisplacement(step, firstPhase, dragSteps, indent, depth, along, dragDistance);
      const elasticity::SolveResult result = solver.solve(positions, acquisition::toolConstraints(scene, tool, displacement));
      allConverged = allConverged && result.converged();
      char name[32];
      std::snprintf(name, sizeof(name), "/step_%03d.obj", step);
      writeObj(outDir + name, surface, positions);
      std::cerr << "step " << step << "/" << firstPhase + dragSteps << ": " << result.message << '\n';
      json iterations = json::array();
      for (const auto& record : result.history)
        iterations.push_back({{"iteration", record.iteration}, {"energy", record.energy}, {"force_norm", record.forceNorm},
                              {"relative_force_norm", record.relativeForceNorm}, {"step_length", record.stepLength},
                              {"line_search_steps", record.lineSearchSteps}, {"regularisation", record.regularisation},
                              {"exact_hessian", record.exactHessian}, {"reused_factorization", record.reusedFactorization},
                              {"assembly_s", record.assemblySeconds}, {"factor_solve_s", record.factorSeconds},
                              {"line_search_s", record.lineSearchSeconds}, {"elapsed_s", record.elapsedSeconds}});
      log["steps"].push_back({{"step", step}, {"tool_displacement", toJson(displacement)},
                              {"status", elasticity::toString(result.status)}, {"converged", result.converged()},
                              {"iterations", result.iterations}, {"initial_force_norm", result.initialForceNorm},
                              {"final_force_norm", result.finalForceNorm}, {"force_tolerance", result.forceTolerance},
                              {"energy", result.energy}, {"seconds", result.seconds}, {"surface", std::string(name + 1)},
                              {"newton", iterations}});
      std::ofstream(outDir + "/log.json") << log.dump(1) << '\n';  // rewritten each step: usable while running
    }
    if (!allConverged) {
      std::cerr << "warning: at least one step did not converge (see log.json)\n";
      return 2;
    }
  } catch (const Error& error) {
    std::cerr << "de_simulate: " << error.what() << '\n';
    return 1;
  }
  return 0;
}
