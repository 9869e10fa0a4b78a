// de_simulate: runs a procedural (or TetGen) scene under a tool that indents and optionally drags
// laterally, solving each step to quasi-static equilibrium with the Stable Neo-Hookean FEM. Writes the
// surface of every step as OBJ and a JSON log of Newton iterations, residuals and times; progress on stderr.
// --check-calculix instead solves the indentation with CalculiX's ccx as well (an independent FEM with a
// compressible neo-Hookean solid, run as a separate program in a temporary folder) and prints the
// difference as JSON, writing no files.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <optional>
#include <sstream>
#include <nlohmann/json.hpp>

#include "deformation_enrichment/elasticity/calculix_comparison.hpp"
#include "deformation_enrichment/elasticity/quasi_static_solver.hpp"
#include "deformation_enrichment/atomic_file.hpp"
#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/tet_surface.hpp"
#include "deformation_enrichment/mesh/tetgen_io.hpp"
#include "deformation_enrichment/scenes/procedural_scene.hpp"
#include "deformation_enrichment/acquisition/tool_loading.hpp"
#include "command_line.hpp"

using namespace deformation_enrichment;
using nlohmann::json;

namespace {

void writeObj(const std::string& path, const mesh::TetSurface& surface, const Eigen::Matrix3Xd& positions) {
  std::ostringstream out;
  out << std::setprecision(9);
  for (int v : surface.surfaceToVolume)
    out << "v " << positions(0, v) << ' ' << positions(1, v) << ' ' << positions(2, v) << '\n';
  for (Eigen::Index f = 0; f < surface.surface.numTriangles(); ++f)
    out << "f " << surface.surface.triangles(0, f) + 1 << ' ' << surface.surface.triangles(1, f) + 1 << ' '
        << surface.surface.triangles(2, f) + 1 << '\n';
  writeFileAtomically(path, out.str());
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

constexpr int kCheckIncrements = 4;       // ccx increments and our load steps of --check-calculix
constexpr double kCheckTolerance = 0.01;  // largest relative difference --check-calculix accepts

scenes::Scene proceduralScene(const std::string& name, const std::vector<int>& cells, std::optional<double> skinThickness,
                              std::optional<int> skinLayers) {
  scenes::Layering layering;
  if (name == "meniscus") layering = scenes::MeniscusOptions().layering;
  if (!cells.empty()) layering.cells = Eigen::Vector3i(cells[0], cells[1], cells[2]);
  if (skinThickness) layering.skinThickness = *skinThickness;
  if (skinLayers) layering.skinLayers = *skinLayers;
  if (name == "slab") {
    scenes::SlabOptions options;
    options.layering = layering;
    return scenes::makeSlab(options);
  }
  if (name == "pillow") {
    scenes::PillowOptions options;
    options.layering = layering;
    return scenes::makePillow(options);
  }
  scenes::MeniscusOptions options;
  options.layering = layering;
  return scenes::makeMeniscus(options);
}

/// The scene indented by the Dirichlet tool of the acquisition (the tool vertices moved by `displacement`,
/// the support held), bulk and skin materials by material id.
elasticity::CalculixModel calculixModel(const scenes::Scene& scene, const std::vector<int>& tool,
                                        const Eigen::Vector3d& displacement,
                                        std::vector<elasticity::IsotropicMaterial> materials, int increments) {
  elasticity::CalculixModel model;
  model.rest = scene.mesh;
  model.materials = std::move(materials);
  model.materialId = scene.materialId;
  model.constraints = acquisition::toolConstraints(scene, tool, displacement);
  model.increments = increments;
  return model;
}

/// Prints the comparison as JSON on stdout; 0 if the relative difference is at most `limit`, else 1.
int checkAgainstCalculix(const elasticity::CalculixModel& model, const std::string& variantName, double depth,
                         std::size_t toolVertices, double limit) {
  elasticity::CalculixComparisonOptions options;
  options.variant = variantName == "paper" ? elasticity::SnhVariant::Paper : elasticity::SnhVariant::Production;
  const elasticity::CalculixComparison c = elasticity::compareWithCalculix(model, options);
  const bool passed = c.relativeDifference <= limit;
  const json report = {
      {"check", "calculix"}, {"variant", variantName}, {"depth", depth}, {"nodes", model.rest.numVertices()},
      {"tets", model.rest.numTets()}, {"tool_vertices", toolVertices}, {"increments", model.increments},
      {"relative_difference", c.relativeDifference}, {"tolerance", limit}, {"passed", passed},
      {"rms_displacement", c.rmsDisplacement}, {"max_difference", c.maxDifference},
      {"max_strain", c.maxGreenStrain}, {"max_displacement_gradient", c.maxDisplacementGradient},
      {"energy_form_remainder", c.energyFormRemainder},
      {"energy_form_explained", 1.0 - c.energyFormRemainder / c.relativeDifference},
      {"calculix_residual_ratio", c.calculixResidualRatio}, {"ccx_seconds", c.calculixSeconds},
      {"ccx_threads", options.calculix.threads}, {"our_seconds", c.ourSeconds}, {"our_iterations", c.ourIterations}};
  std::cout << report.dump(1) << '\n';
  if (passed) return 0;
  std::cerr << "de_simulate: relative difference to CalculiX " << c.relativeDifference << " exceeds the tolerance " << limit << '\n';
  return 1;
}

struct Options {
  std::string sceneName = "slab", tetgenBase, outDir = "de_simulate_out", variantName = "paper", solverName = "auto";
  std::string mode = "indent";
  std::vector<int> cells;
  double skinThickness = 0.0, bulkYoung = 1e4, bulkPoisson = 0.45, skinYoung = 1e6, skinPoisson = 0.3;
  int skinLayers = 0, steps = 10, indentSteps = 4, maxIterations = 100;
  std::vector<double> point{0.0, 0.0}, indentDirection{0.0, 0.0, -1.0}, dragDirection{1.0, 0.0, 0.0};
  double toolRadius = 0.004, depth = 0.004, dragDistance = 0.01, tolerance = 1e-8, maxSeconds = 600.0, fixTolerance = 1e-6;
  double exactBelow = elasticity::SolverOptions().exactHessianBelow;
  double reuseContraction = elasticity::SolverOptions().reuseContraction;
  double preconditionedTolerance = elasticity::SolverOptions().preconditionedTolerance;
  bool checkCalculix = false;
  CLI::Option *skinThicknessOption = nullptr, *skinLayersOption = nullptr, *stepsOption = nullptr, *toleranceOption = nullptr;
};

void addOptions(CLI::App& app, Options& o) {
  app.add_option("--scene", o.sceneName, "slab | pillow | meniscus")->check(CLI::IsMember({"slab", "pillow", "meniscus"}));
  app.add_option("--tetgen", o.tetgenBase, "read <base>.node/.ele instead (lowest z fixed, highest z is the top)");
  app.add_option("--fix-tolerance", o.fixTolerance, "TetGen scenes: z tolerance of the support and top layers (m)");
  app.add_option("--cells", o.cells, "cells: first, second surface direction, bulk thickness (3 integers)")->expected(3);
  o.skinThicknessOption = app.add_option("--skin-thickness", o.skinThickness, "skin thickness in m (0 = no skin; default: the scene's)");
  o.skinLayersOption = app.add_option("--skin-layers", o.skinLayers, "cell layers through the skin (default: the scene's)");
  app.add_option("--bulk-young", o.bulkYoung, "bulk Young's modulus (Pa)");
  app.add_option("--bulk-poisson", o.bulkPoisson, "bulk Poisson ratio");
  app.add_option("--skin-young", o.skinYoung, "skin Young's modulus (Pa)");
  app.add_option("--skin-poisson", o.skinPoisson, "skin Poisson ratio");
  app.add_option("--variant", o.variantName, "paper | production")->check(CLI::IsMember({"paper", "production"}));
  app.add_option("--mode", o.mode, "indent | drag")->check(CLI::IsMember({"indent", "drag"}));
  app.add_option("--point", o.point, "tool position x y on the top surface (m)")->expected(2);
  app.add_option("--tool-radius", o.toolRadius, "tool footprint radius (m)");
  app.add_option("--depth", o.depth, "indentation depth (m)");
  app.add_option("--indent-direction", o.indentDirection, "indentation direction (3 numbers)")->expected(3);
  app.add_option("--direction", o.dragDirection, "drag direction (3 numbers)")->expected(3);
  app.add_option("--drag-distance", o.dragDistance, "drag distance (m)");
  o.stepsOption = app.add_option("--steps", o.steps, "steps of the motion (indent mode: indentation steps; drag mode: drag steps)");
  app.add_option("--indent-steps", o.indentSteps, "drag mode: indentation steps before the drag");
  app.add_option("--solver", o.solverName, "auto | cholmod | ldlt")->check(CLI::IsMember({"auto", "cholmod", "ldlt"}));
  app.add_option("--max-iterations", o.maxIterations, "Newton iterations per step");
  o.toleranceOption = app.add_option("--tolerance", o.tolerance, "relative force tolerance (with --check-calculix: the "
                                     "largest relative difference accepted, default 0.01)");
  app.add_flag("--check-calculix", o.checkCalculix,
               "solve the indentation (Dirichlet tool) with CalculiX's ccx too and print the difference as JSON; "
               "exit 1 if it exceeds --tolerance");
  app.add_option("--max-seconds", o.maxSeconds, "time limit per step (s)");
  app.add_option("--exact-below", o.exactBelow, "try the exact Hessian once |f| <= this fraction of |f_0| (0 = never)");
  app.add_option("--reuse-contraction", o.reuseContraction, "reuse a factorisation after a step shrinking |f| to this fraction (0 = never)");
  app.add_option("--preconditioned-tolerance", o.preconditionedTolerance,
                 "conjugate gradients preconditioned by the last factorisation, to this relative residual, before "
                 "a new factorisation (0 = always factorise)");
  app.add_option("--out", o.outDir, "output directory (OBJ per step, log.json)");
}

elasticity::SolverOptions solverSettings(const Options& o) {
  elasticity::SolverOptions settings;
  settings.maxIterations = o.maxIterations;
  settings.relativeForceTolerance = o.tolerance;
  settings.maxSeconds = o.maxSeconds;
  settings.exactHessianBelow = o.exactBelow;
  settings.reuseContraction = o.reuseContraction;
  settings.preconditionedTolerance = o.preconditionedTolerance;
  settings.linearSolver = o.solverName == "cholmod" ? numerics::SparseCholeskyBackend::Cholmod
                          : o.solverName == "ldlt"  ? numerics::SparseCholeskyBackend::EigenSimplicial
                                                    : numerics::SparseCholeskyBackend::Default;
  return settings;
}

json newtonLog(const elasticity::SolveResult& result) {
  json iterations = json::array();
  for (const auto& record : result.history)
    iterations.push_back({{"iteration", record.iteration}, {"energy", record.energy}, {"force_norm", record.forceNorm},
                          {"relative_force_norm", record.relativeForceNorm}, {"step_length", record.stepLength},
                          {"line_search_steps", record.lineSearchSteps}, {"regularisation", record.regularisation},
                          {"exact_hessian", record.exactHessian}, {"reused_factorization", record.reusedFactorization},
                          {"conjugate_gradient_iterations", record.conjugateGradientIterations},
                          {"assembly_s", record.assemblySeconds}, {"factor_solve_s", record.factorSeconds},
                          {"line_search_s", record.lineSearchSeconds}, {"elapsed_s", record.elapsedSeconds}});
  return iterations;
}

/// Solves every step of the motion, writing its surface and the log as it goes. 0, or 2 when a step did not
/// converge.
int simulateMotion(const Options& o, const scenes::Scene& scene, const std::vector<int>& tool, const Eigen::Vector3d& indent) {
  const elasticity::SnhVariant variant = o.variantName == "paper" ? elasticity::SnhVariant::Paper : elasticity::SnhVariant::Production;
  const auto bulk = elasticity::lameFromYoungPoisson(o.bulkYoung, o.bulkPoisson);
  const auto skin = elasticity::lameFromYoungPoisson(o.skinYoung, o.skinPoisson);
  const elasticity::TetFem fem(scene.mesh,
                               {elasticity::StableNeoHookean(bulk.mu, bulk.lambda, variant),
                                elasticity::StableNeoHookean(skin.mu, skin.lambda, variant)},
                               scene.materialId);
  elasticity::QuasiStaticSolver solver(fem, solverSettings(o));
  const mesh::TetSurface surface = mesh::extractSurface(scene.mesh);
  std::filesystem::create_directories(o.outDir);
  const bool drag = o.mode == "drag";
  const int firstPhase = drag ? o.indentSteps : o.steps, dragSteps = drag ? o.steps : 0;
  const Eigen::Vector3d along(o.dragDirection[0], o.dragDirection[1], o.dragDirection[2]);
  std::cerr << "scene " << scene.name << ": " << scene.mesh.numVertices() << " vertices, " << scene.mesh.numTets()
            << " tets, " << tool.size() << " tool vertices, " << scene.fixedVertices.size() << " support vertices\n";
  json log;
  log["scene"] = {{"name", scene.name}, {"vertices", scene.mesh.numVertices()}, {"tets", scene.mesh.numTets()},
                  {"tool_vertices", tool.size()}, {"support_vertices", scene.fixedVertices.size()}};
  log["settings"] = {{"mode", o.mode}, {"variant", o.variantName}, {"solver", o.solverName}, {"depth", o.depth},
                     {"drag_distance", o.dragDistance}, {"tool_radius", o.toolRadius}, {"tolerance", o.tolerance}};
  log["steps"] = json::array();
  Eigen::Matrix3Xd positions = scene.mesh.vertices;
  writeObj(o.outDir + "/step_000.obj", surface, positions);
  bool allConverged = true;
  for (int step = 1; step <= firstPhase + dragSteps; ++step) {
    const Eigen::Vector3d displacement = acquisition::toolDisplacement(step, firstPhase, dragSteps, indent, o.depth, along, o.dragDistance);
    const elasticity::SolveResult result = solver.solve(positions, acquisition::toolConstraints(scene, tool, displacement));
    allConverged = allConverged && result.converged();
    char name[32];
    std::snprintf(name, sizeof(name), "/step_%03d.obj", step);
    writeObj(o.outDir + name, surface, positions);
    std::cerr << "step " << step << "/" << firstPhase + dragSteps << ": " << result.message << '\n';
    log["steps"].push_back({{"step", step}, {"tool_displacement", toJson(displacement)},
                            {"status", elasticity::toString(result.status)}, {"converged", result.converged()},
                            {"iterations", result.iterations}, {"initial_force_norm", result.initialForceNorm},
                            {"final_force_norm", result.finalForceNorm}, {"force_tolerance", result.forceTolerance},
                            {"energy", result.energy}, {"seconds", result.seconds}, {"surface", std::string(name + 1)},
                            {"newton", newtonLog(result)}});
    writeFileAtomically(o.outDir + "/log.json", log.dump(1) + '\n');  // rewritten each step: usable while running
  }
  if (allConverged) return 0;
  std::cerr << "warning: at least one step did not converge (see log.json)\n";
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Quasi-static Stable Neo-Hookean simulation of a tool indenting / dragging a soft-tissue scene"};
  Options o;
  addOptions(app, o);
  if (const auto exitCode = deformation_enrichment::tools::parseCommandLine(app, argc, argv)) return *exitCode;
  try {
    const std::optional<double> thickness = o.skinThicknessOption->count() ? std::optional<double>(o.skinThickness) : std::nullopt;
    const std::optional<int> layers = o.skinLayersOption->count() ? std::optional<int>(o.skinLayers) : std::nullopt;
    const scenes::Scene scene = o.tetgenBase.empty() ? proceduralScene(o.sceneName, o.cells, thickness, layers)
                                                     : sceneFromTetGen(o.tetgenBase, o.fixTolerance);
    const Eigen::Vector3d indent(o.indentDirection[0], o.indentDirection[1], o.indentDirection[2]);
    const std::vector<int> tool = acquisition::toolFootprint(scene, Eigen::Vector2d(o.point[0], o.point[1]), o.toolRadius);
    if (!o.checkCalculix) return simulateMotion(o, scene, tool, indent);
    if (o.mode != "indent") throw InvalidInputError("--check-calculix compares an indentation; --mode drag is not supported");
    const elasticity::CalculixModel model = calculixModel(scene, tool,
                                                          acquisition::toolDisplacement(1, 1, 0, indent, o.depth, Eigen::Vector3d::UnitX(), 0.0),
                                                          {{o.bulkYoung, o.bulkPoisson}, {o.skinYoung, o.skinPoisson}},
                                                          o.stepsOption->count() ? o.steps : kCheckIncrements);
    return checkAgainstCalculix(model, o.variantName, o.depth, tool.size(), o.toleranceOption->count() ? o.tolerance : kCheckTolerance);
  } catch (const Error& error) {
    std::cerr << "de_simulate: " << error.what() << '\n';
    return 1;
  }
}
