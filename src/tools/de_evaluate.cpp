// de_evaluate: held-out accuracy of the enrichment on any scene, with an example set of the same scene or of
// another one (transfer across objects, [Seiler14 §1]). It runs the coarse and the fine simulation (ground
// truth) of each held-out contact once (random, seeded, unless given), enriches the coarse state with the
// example set and prints one JSON object: RMS errors against the fine solution over the fine surface vertices within
// the stamp radius, per-contact details, maxima and compute time per frame. With --curves it also scores
// run-time variants on the same solves: error vs number of examples ([Seiler14 Fig. 7]) and run time vs
// error over stamp resolution and Hermite orders (plot them with scripts/plot_evaluation).
#include <CLI/CLI.hpp>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>

#include "deformation_enrichment/acquisition/held_out_evaluation.hpp"
#include "deformation_enrichment/acquisition/plan_generation.hpp"
#include "deformation_enrichment/enrichment/example_set_options.hpp"
#include "deformation_enrichment/enrichment/example_set_reduction.hpp"
#include "deformation_enrichment/enrichment/material_similarity.hpp"
#include "deformation_enrichment/enrichment/surface_enricher.hpp"
#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/examples/example_set_io.hpp"

using namespace deformation_enrichment;
using nlohmann::json;

namespace {

json vec(const Eigen::Vector3d& v) { return json::array({v.x(), v.y(), v.z()}); }

// The display surface without the triangles whose three vertices are held by the fixed region: the open
// surface a simulator publishing only the free (visible) part would send. Vertices are kept, so coarse
// and fine states still match it vertex for vertex.
mesh::TriangleMesh openSurface(const scenes::SceneModels& models) {
  std::vector<char> held(static_cast<std::size_t>(models.fine.mesh.numVertices()), 0);
  for (int v : models.fine.fixedVertices) held[static_cast<std::size_t>(v)] = 1;
  const mesh::TriangleMesh& closed = models.surface;
  mesh::TriangleMesh open{closed.vertices, Eigen::Matrix3Xi(3, 0)};
  for (Eigen::Index t = 0; t < closed.numTriangles(); ++t) {
    bool allHeld = true;
    for (int k = 0; k < 3; ++k) allHeld = allHeld && held[static_cast<std::size_t>(models.surfaceToFine[closed.triangles(k, t)])];
    if (allHeld) continue;
    open.triangles.conservativeResize(3, open.triangles.cols() + 1);
    open.triangles.col(open.triangles.cols() - 1) = closed.triangles.col(t);
  }
  if (open.numTriangles() == closed.numTriangles()) throw InvalidInputError("--open: no triangle of the display surface is held");
  return open;
}

json summary(const acquisition::HeldOutScore& s) {
  return {{"ratio", s.ratio()}, {"enriched_rms", s.enrichedRms}, {"coarse_rms", s.coarseRms},
          {"seconds_per_frame", s.secondsPerFrame}};
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Held-out error of coarse vs enriched surfaces against the fine simulation, on any scene"};
  std::string sceneName = "slab", setPath, contactsPath;
  bool asJson = false, noFit = false, correlationOnly = false, curves = false;
  const enrichment::ContactEnricherOptions defaults;
  double gain = 1.0, rimBand = defaults.rimBand, sigmaRho = 0.0, sigmaU = 0.0;
  int repetitions = 5, heldOut = 8;
  unsigned seed = 1;
  double lambda = enrichment::RbfInterpolator::kDefaultRegularisation;
  app.add_option("--lambda", lambda, "RBF regularisation lambda of (K^2 + lambda^2 I)^-1 K")->check(CLI::PositiveNumber);
  app.add_option("--scene", sceneName, "scene to evaluate on: shipped name or scene file (.yaml)");
  app.add_option("--examples", setPath, "example set directory (any scene's: transfer), or 'default' (the scene's "
                                        "default set, acquired on first use)")->required();
  app.add_option("--contacts", contactsPath, "CSV x,y,z,depth,dx,dy,dz per held-out interaction (default: random)");
  app.add_option("--held-out", heldOut, "random held-out interactions without --contacts")->check(CLI::PositiveNumber);
  app.add_option("--seed", seed, "seed of the random held-out interactions");
  app.add_option("--gain", gain, "stamp gain");
  app.add_option("--rim-band", rimBand, "StampMapper rim band in [0, 1)");
  app.add_flag("--correlation-only", correlationOnly, "the paper's pure correlation (no |mu| / |mu[i]| stamp scaling)");
  app.add_option("--sigma-rho", sigmaRho, "fixed kernel width sigma_rho (with --sigma-u: no leave-one-out fit)");
  app.add_option("--sigma-u", sigmaU, "fixed kernel width sigma_u");
  app.add_flag("--no-fit", noFit, "keep default kernel widths instead of the leave-one-out fit");
  bool noGain = false;
  app.add_flag("--no-cv-gain", noGain, "do not scale w~ by the cross-validated gain of the fit");
  app.add_flag("--curves", curves, "also score example count, stamp resolution and Hermite order variants");
  bool open = false;
  std::string densitySource = "auto";
  double shellThickness = 0.0;
  app.add_flag("--open", open, "enrich the display surface without its held triangles (an open surface), as the node would");
  app.add_option("--site-density", densitySource, "rho's density: auto, surface, volume (the scene's coarse volume) or shell")
      ->capture_default_str();
  app.add_option("--shell-thickness", shellThickness, "shell depth in metres (0: three window scales)")->capture_default_str();
  app.add_option("--repetitions", repetitions, "enrichments per contact for the median compute time")->check(CLI::PositiveNumber);
  app.add_flag("--json", asJson, "print JSON (always on; kept for the documented command line)");
  CLI11_PARSE(app, argc, argv);
  try {
    if (!(sigmaRho >= 0.0) || !(sigmaU >= 0.0) || !std::isfinite(sigmaRho) || !std::isfinite(sigmaU))
      throw InvalidInputError("--sigma-rho and --sigma-u must be finite and >= 0 (0: fitted)");
    const scene_file::SceneDescription scene = scene_file::readSceneFile(scene_file::findSceneFile(sceneName));
    std::cerr << "scene " << scene.name << ": building the coarse and fine models...\n";
    acquisition::SceneAcquisition acq(scene);
    if (setPath == "default") {
      setPath = acquisition::defaultExampleSetDirectory(scene.name);
      if (!std::filesystem::exists(std::filesystem::path(setPath) / examples::kManifestFile)) {
        std::cerr << "acquiring the default " << scene.name << " example set into " << setPath << " (once)\n";
        const auto plan = scene.plan == "auto" ? acquisition::autoPlan(acq, 12) : acquisition::readPlan(scene.plan);
        acq.acquireSet(plan, setPath, &std::cerr);
      }
    }
    const examples::ExampleSet set = examples::loadExampleSet(setPath);
    const std::string source = set.metadata.provenance ? set.metadata.provenance->scene.name : set.metadata.scene;
    const bool transfer = source != scene.name;
    const auto contacts = contactsPath.empty() ? acquisition::randomContacts(acq, heldOut, seed) : acquisition::readPlan(contactsPath);
    // The evaluation scene's surface, described as the set's examples were.
    enrichment::ContactEnricherOptions options = defaults;
    options.stampGain = gain;
    options.rimBand = rimBand;
    options.magnitudeAware = !correlationOnly;
    options = enrichment::optionsFor(set, options);
    // Detail of another tissue fades with its material's difference (the descriptors see geometry only).
    const double similarity = set.metadata.provenance ? enrichment::materialSimilarity(set.metadata.provenance->scene, scene) : 1.0;
    options.stampGain *= similarity;
    descriptors::SiteDensityOptions density;
    density.source = descriptors::parseSiteDensitySource(densitySource);
    density.shellThickness = shellThickness;
    density.maxOutside = scene.maxOutside;
    std::string densityDescription;
    const mesh::TriangleMesh surface = open ? openSurface(acq.models()) : acq.fineSurface();
    const mesh::TetMesh* volume = &acq.models().coarse.mesh;
    enrichment::ContactEnricher enricher = enrichment::surfaceEnricher(surface, volume, options, density, &densityDescription);
    std::cerr << "site density: " << densityDescription << "\n";
    enrichment::ExampleBlenderOptions blenderOptions;
    blenderOptions.fitWidths = !noFit && !(sigmaRho > 0.0 && sigmaU > 0.0);
    blenderOptions.lambda = lambda;
    blenderOptions.crossValidatedGain = !noGain;
    if (sigmaRho > 0.0 && sigmaU > 0.0) blenderOptions.widths = enrichment::KernelWidths{sigmaRho, sigmaU};
    // Leave-one-out needs at least two examples to leave one out.
    const auto blenderFor = [&](const examples::ExampleSet& s) {
      enrichment::ExampleBlenderOptions o = blenderOptions;
      o.fitWidths = o.fitWidths && s.examples.size() >= 2;
      return o;
    };
    enricher.setExamples(set, blenderFor(set));
    const enrichment::KernelWidths widths = enricher.blender()->widths();

    const std::vector<acquisition::HeldOutCase> cases = acquisition::simulateHeldOut(acq, contacts, [&](std::size_t i) {
      std::cerr << "[" << i + 1 << "/" << contacts.size() << "] simulating coarse and fine...\n";
    });
    const acquisition::HeldOutScore score = acquisition::scoreHeldOut(enricher, cases, repetitions);

    json perContact = json::array();
    for (std::size_t i = 0; i < cases.size(); ++i) {
      const acquisition::PlanEntry& c = cases[i].entry;
      const acquisition::InteractionResult& r = cases[i].result;
      const acquisition::ContactScore& s = score.contacts[i];
      const Eigen::VectorXd& w = s.outcome.weights;
      perContact.push_back({{"point", vec(c.point)}, {"contact", vec(cases[i].contact.point)}, {"depth", c.depth},
                            {"drag", vec(c.drag)}, {"vertices", s.vertices},
                            {"coarse_rms", s.coarseRms}, {"enriched_rms", s.enrichedRms}, {"coarse_max", s.coarseMax},
                            {"enriched_max", s.enrichedMax}, {"confidence", s.outcome.confidence},
                            {"weights", std::vector<double>(w.data(), w.data() + w.size())},
                            {"frame_rule", descriptors::toString(s.outcome.description.frameRule)},
                            {"converged", r.converged}, {"coarse_seconds", r.coarseSeconds}, {"fine_seconds", r.fineSeconds},
                            {"enrich_seconds", s.timings.totalSeconds}, {"descriptor_seconds", s.timings.descriptorSeconds},
                            {"blend_seconds", s.timings.blendSeconds}, {"map_seconds", s.timings.mapSeconds}});
    }
    json out = {{"scene", scene.name}, {"source_scene", source}, {"transfer", transfer}, {"material_similarity", similarity},
                {"examples", set.examples.size()}, {"example_set", setPath}, {"contacts", contacts.size()},
                {"held_out", contactsPath.empty() ? json{{"random", heldOut}, {"seed", seed}} : json{{"file", contactsPath}}},
                {"stamp_radius", options.stampRadius}, {"open_surface", open}, {"site_density", densityDescription},
                {"magnitude_aware", !correlationOnly}, {"rim_band", rimBand}, {"gain", gain}, {"lambda", lambda},
                {"surface_vertices", acq.fineSurface().vertices.cols()},
                {"sigma_rho", widths.sigmaRho}, {"sigma_u", widths.sigmaU},
                {"leave_one_out", enricher.blender()->fit() ? json{{"error", enricher.blender()->fit()->bestError},
                                                                   {"gain", enricher.blender()->gain()},
                                                                   {"error_with_gain", enricher.blender()->fit()->gainedError}}
                                                            : json(nullptr)},
                {"coarse_rms", score.coarseRms}, {"enriched_rms", score.enrichedRms}, {"ratio", score.ratio()},
                {"coarse_max", score.coarseMax}, {"enriched_max", score.enrichedMax},
                {"compute_seconds_per_frame", score.secondsPerFrame}, {"per_contact", perContact}};

    if (curves) {
      json byCount = json::array(), byResolution = json::array(), byOrder = json::array();
      for (std::size_t k = 1; k <= set.examples.size(); ++k) {
        examples::ExampleSet first = set;
        first.examples.resize(k);
        enricher.setExamples(first, blenderFor(first));
        json entry = summary(acquisition::scoreHeldOut(enricher, cases, repetitions));
        entry["examples"] = k;
        byCount.push_back(entry);
        std::cerr << "examples " << k << ": ratio " << entry["ratio"] << "\n";
      }
      const int native = set.examples.front().stamp.rows;
      for (int n : {8, 16, 32, 64}) {
        if (n > native) break;
        const examples::ExampleSet reduced = enrichment::withStampResolution(set, n);
        enricher.setExamples(reduced, blenderFor(reduced));
        json entry = summary(acquisition::scoreHeldOut(enricher, cases, repetitions));
        entry["stamp_resolution"] = n;
        byResolution.push_back(entry);
        std::cerr << "stamp resolution " << n << ": ratio " << entry["ratio"] << "\n";
      }
      const int siteOrders = set.examples.front().rho.lastOrder(), deformationOrders = set.examples.front().mu.lastOrder();
      for (int m = 1; m <= deformationOrders; ++m)
        for (int n = 1; n <= siteOrders; ++n) {  // rho_1 defines the stamping frame
          enrichment::ContactEnricherOptions orderOptions = options;
          orderOptions.descriptors.siteOrder = n;
          orderOptions.descriptors.deformationOrder = m;
          enrichment::ContactEnricher variant = enrichment::surfaceEnricher(surface, volume, orderOptions, density);
          const examples::ExampleSet reduced = enrichment::withHermiteOrders(set, n, m);
          variant.setExamples(reduced, blenderFor(reduced));
          json entry = summary(acquisition::scoreHeldOut(variant, cases, repetitions));
          entry["site_order"] = n;
          entry["deformation_order"] = m;
          byOrder.push_back(entry);
          std::cerr << "orders rho " << n << ", mu " << m << ": ratio " << entry["ratio"] << "\n";
        }
      out["examples_curve"] = byCount;
      out["stamp_resolution_curve"] = byResolution;
      out["hermite_order_curve"] = byOrder;
    }
    std::cout << out.dump(2) << std::endl;
  } catch (const std::exception& e) {
    std::cerr << "de_evaluate: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
