// de_evaluate: held-out accuracy of the enrichment on any scene, with an example set of the same scene or of
// another one (transfer across objects, [Seiler14 §1]). It runs the coarse and the fine simulation (ground
// truth) of each held-out contact once (random, seeded, unless given), enriches the coarse state with the
// example set and prints one JSON object: RMS errors against the fine solution over the fine surface vertices
// within the stamp radius, per-contact details and bounds (held_out_evaluation.hpp), maxima and compute time
// per frame. --calibrate scales another scene's set by a gain calibrated on fresh contacts of this one
// (transfer_calibration.hpp). --learning-curve scores prefixes of the set (error against number of examples,
// [Seiler14 Fig. 7]); --curves scores stamp resolutions and Hermite orders (run time against error). Plot
// both with scripts/plot_evaluation.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "deformation_enrichment/acquisition/held_out_evaluation.hpp"
#include "deformation_enrichment/acquisition/plan_generation.hpp"
#include "deformation_enrichment/acquisition/transfer_calibration.hpp"
#include "deformation_enrichment/enrichment/example_set_options.hpp"
#include "deformation_enrichment/enrichment/example_set_reduction.hpp"
#include "deformation_enrichment/enrichment/material_similarity.hpp"
#include "deformation_enrichment/enrichment/surface_enricher.hpp"
#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/examples/example_set_io.hpp"
#ifdef DE_COARSE_BAG
#include "deformation_enrichment/ros/coarse_bag.hpp"
#endif
#include "command_line.hpp"

using namespace deformation_enrichment;
using nlohmann::json;

namespace {

struct EvaluateOptions {
  std::string scene = "slab", set, contacts, learningCurve, densitySource = "auto", blend = "regression", coarseBag;
  std::vector<std::string> alsoSets;
  bool noFit = false, correlationOnly = false, curves = false, noGain = false, open = false;
  const enrichment::ContactEnricherOptions defaults;
  double minConfidence = 0.0, maxWeightNorm = defaults.gain.maxWeightNorm, gain = 1.0, rimBand = defaults.rimBand;
  double sigmaRho = 0.0, sigmaU = 0.0, shellThickness = 0.0;
  double lambda = enrichment::RbfInterpolator::kDefaultRegularisation;
  int repetitions = 5, heldOut = 8, calibrate = 0;
  unsigned seed = 1;
  std::optional<unsigned> calibrationSeed;
};

void addOptions(CLI::App& app, EvaluateOptions& s) {
  app.add_option("--scene", s.scene, "scene to evaluate on: shipped name or scene file (.yaml)");
  app.add_option("--examples", s.set, "example set directory (any scene's: transfer), or 'default' (the scene's "
                                      "default set, acquired on first use)")->required();
  app.add_option("--contacts", s.contacts, "CSV x,y,z,depth,dx,dy,dz per held-out interaction (default: random)");
#ifdef DE_COARSE_BAG
  app.add_option("--coarse-bag", s.coarseBag, "held-out interactions recorded from another coarse simulator: acquisition_driver's "
                 "bag (its plan) or a session of servo_cp and mesh_state (the plan from --contacts); settled states as the coarse half")
      ->check(CLI::ExistingFile);
#endif
  app.add_option("--also-examples", s.alsoSets, "more example sets scored on the same held-out interactions (the same scene, "
                 "descriptors and stamp radius as --examples); one row each under \"also\"");
  app.add_option("--held-out", s.heldOut, "random held-out interactions without --contacts")->check(CLI::PositiveNumber);
  app.add_option("--seed", s.seed, "seed of the random held-out interactions");
  app.add_option("--calibrate", s.calibrate, "transfer calibration (transfer_calibration.hpp): solve this many random contacts of "
                 "the scene and scale the set's stamps by the smallest limit they allow (a contact's best gain, or 5 % worse "
                 "than coarse where its detail points away) instead of the material similarity (the node's ~transfer_gain; "
                 "0: no calibration)")->check(CLI::NonNegativeNumber);
  app.add_option("--calibration-seed", s.calibrationSeed, "seed of the calibration contacts (default: --seed + 1; never --seed)");
  app.add_option("--learning-curve", s.learningCurve,
                 "ascending sizes N1,N2,...: score the first N examples of the set for each (a nested plan's prefixes "
                 "are the smaller sets)");
  app.add_option("--blend", s.blend, "how examples are blended: regression (stamp_regression.hpp) or paper ([Seiler14] "
                                     "eq. 15 weights + RBF)")->capture_default_str();
  app.add_option("--lambda", s.lambda, "RBF regularisation lambda of (K^2 + lambda^2 I)^-1 K")->check(CLI::PositiveNumber);
  app.add_option("--gain", s.gain, "stamp gain");
  app.add_option("--min-confidence", s.minConfidence, "detail fades from full at twice this blend confidence to none at it "
                 "(the node's ~min_confidence; 0: no gate)")->check(CLI::Range(0.0, 1.0));
  app.add_option("--max-weight-norm", s.maxWeightNorm, "blend regression: detail scaled by min(1, this / sum |w_i|) (the node's "
                 "~max_weight_norm; 0: no bound)")->check(CLI::NonNegativeNumber)->capture_default_str();
  app.add_option("--rim-band", s.rimBand, "StampMapper rim band in [0, 1)");
  app.add_flag("--correlation-only", s.correlationOnly, "the paper's pure correlation (no |mu| / |mu[i]| stamp scaling)");
  app.add_option("--sigma-rho", s.sigmaRho, "fixed kernel width sigma_rho (with --sigma-u: no leave-one-out fit)");
  app.add_option("--sigma-u", s.sigmaU, "fixed kernel width sigma_u");
  app.add_flag("--no-fit", s.noFit, "keep default kernel widths instead of the leave-one-out fit");
  app.add_flag("--no-cv-gain", s.noGain, "do not scale w~ by the cross-validated gain of the fit");
  app.add_flag("--curves", s.curves, "also score stamp resolution and Hermite order variants");
  app.add_flag("--open", s.open, "enrich the display surface without its held triangles (an open surface), as the node would");
  app.add_option("--site-density", s.densitySource, "rho's density: auto, surface, volume (the scene's coarse volume) or shell")
      ->capture_default_str();
  app.add_option("--shell-thickness", s.shellThickness, "shell depth in metres (0: three window scales)")->capture_default_str();
  app.add_option("--repetitions", s.repetitions, "enrichments per contact for the median compute time")->check(CLI::PositiveNumber);
  app.add_flag("--json", "print JSON (always on; kept for the documented command line)");
}

json vec(const Eigen::Vector3d& v) { return json::array({v.x(), v.y(), v.z()}); }

// Strictly ascending positive sizes, none larger than the set.
std::vector<std::size_t> parseSizes(const std::string& text, std::size_t setSize) {
  std::vector<std::size_t> sizes;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    std::size_t used = 0;
    long n = 0;
    try {
      n = std::stol(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != item.size() || n < 1) throw InvalidInputError("--learning-curve: '" + item + "' is not a positive size");
    if (static_cast<std::size_t>(n) > setSize)
      throw InvalidInputError("--learning-curve: size " + item + " is larger than the set (" + std::to_string(setSize) + " examples)");
    if (!sizes.empty() && static_cast<std::size_t>(n) <= sizes.back())
      throw InvalidInputError("--learning-curve: sizes must ascend strictly, got " + text);
    sizes.push_back(static_cast<std::size_t>(n));
  }
  if (sizes.empty()) throw InvalidInputError("--learning-curve: no size given");
  return sizes;
}

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

// The factor on the stamp gain with the least squared per-contact ratios given the truth, and the ratios at
// it: null when no contact got detail.
json gainGivenTruth(const acquisition::HeldOutScore& s) {
  if (std::none_of(s.contacts.begin(), s.contacts.end(), [](const auto& c) { return c.detailSize > 0.0; })) return nullptr;
  const double factor = s.bestGain();
  return {{"factor", factor}, {"mean_ratio", s.meanRatioAtGain(factor)}, {"worst_ratio", s.worstRatioAtGain(factor)}};
}

json summary(const acquisition::HeldOutScore& s) {
  return {{"ratio", s.ratio()}, {"mean_ratio", s.meanRatio()}, {"worst_ratio", s.worstRatio()},
          {"enriched_rms", s.enrichedRms}, {"coarse_rms", s.coarseRms}, {"seconds_per_frame", s.secondsPerFrame},
          {"gain_given_truth", gainGivenTruth(s)}};
}

// Everything one evaluation needs: the scene, its solves, the set and the enricher it is scored with.
struct Evaluation {
  EvaluateOptions settings;
  scene_file::SceneDescription scene;
  std::unique_ptr<acquisition::SceneAcquisition> acquisition;
  examples::ExampleSet set;
  std::string source;  // the scene the set was acquired on
  double similarity = 1.0;
  double stampScale = 1.0;  // the set's stamps are scaled by this: the similarity or the calibrated transfer gain
  json calibration = nullptr;
  enrichment::ContactEnricherOptions options;
  descriptors::SiteDensityOptions density;
  std::string densityDescription;
  mesh::TriangleMesh surface;
  std::optional<enrichment::ContactEnricher> enricher;
  enrichment::ExampleBlenderOptions blenderOptions;

  // Leave-one-out needs at least two examples to leave one out.
  enrichment::ExampleBlenderOptions blenderFor(const examples::ExampleSet& s) const {
    enrichment::ExampleBlenderOptions o = blenderOptions;
    o.fitWidths = o.fitWidths && s.examples.size() >= 2;
    return o;
  }
  enrichment::ContactEnricher makeEnricher(const enrichment::ContactEnricherOptions& o) const {
    return enrichment::surfaceEnricher(surface, &acquisition->models().coarse.mesh, o, density);
  }
};

examples::ExampleSet loadOrAcquireSet(Evaluation& ev) {
  std::string& path = ev.settings.set;
  if (path == "default") {
    path = acquisition::defaultExampleSetDirectory(ev.scene.name);
    if (!std::filesystem::exists(std::filesystem::path(path) / examples::kManifestFile)) {
      std::cerr << "acquiring the default " << ev.scene.name << " example set into " << path << " (once)\n";
      ev.acquisition->acquireSet(acquisition::scenePlan(*ev.acquisition), path, &std::cerr);
    }
  }
  return examples::loadExampleSet(path);
}

void prepare(Evaluation& ev) {
  const EvaluateOptions& s = ev.settings;
  if (!(s.sigmaRho >= 0.0) || !(s.sigmaU >= 0.0) || !std::isfinite(s.sigmaRho) || !std::isfinite(s.sigmaU))
    throw InvalidInputError("--sigma-rho and --sigma-u must be finite and >= 0 (0: fitted)");
  ev.scene = scene_file::readSceneFile(scene_file::findSceneFile(s.scene));
  std::cerr << "scene " << ev.scene.name << ": building the coarse and fine models...\n";
  ev.acquisition = std::make_unique<acquisition::SceneAcquisition>(ev.scene);
  ev.set = loadOrAcquireSet(ev);
  ev.source = ev.set.metadata.provenance ? ev.set.metadata.provenance->scene.name : ev.set.metadata.scene;
  // The evaluation scene's surface, described as the set's examples were.
  ev.options = s.defaults;
  ev.options.gain.stampGain = s.gain;
  ev.options.gain.minConfidence = s.minConfidence;
  ev.options.gain.maxWeightNorm = s.maxWeightNorm;
  ev.options.rimBand = s.rimBand;
  ev.options.magnitudeAware = !s.correlationOnly;
  ev.options = enrichment::optionsFor(ev.set, ev.options);
  // Detail of another tissue fades with its material's difference (the descriptors see geometry only).
  if (ev.set.metadata.provenance) ev.similarity = enrichment::materialSimilarity(ev.set.metadata.provenance->scene, ev.scene);
  ev.stampScale = ev.similarity;
  ev.options.gain.stampGain *= ev.stampScale;
  ev.density.source = descriptors::parseSiteDensitySource(s.densitySource);
  ev.density.shellThickness = s.shellThickness;
  ev.density.maxOutside = ev.scene.maxOutside;
  ev.surface = s.open ? openSurface(ev.acquisition->models()) : ev.acquisition->fineSurface();
  ev.enricher.emplace(enrichment::surfaceEnricher(ev.surface, &ev.acquisition->models().coarse.mesh, ev.options, ev.density,
                                                  &ev.densityDescription));
  std::cerr << "site density: " << ev.densityDescription << "\n";
  const bool fixedWidths = s.sigmaRho > 0.0 && s.sigmaU > 0.0;
  ev.blenderOptions.method = enrichment::parseBlendMethod(s.blend);
  ev.blenderOptions.fitWidths = !s.noFit && !fixedWidths;
  ev.blenderOptions.lambda = s.lambda;
  ev.blenderOptions.crossValidatedGain = !s.noGain;
  if (fixedWidths) ev.blenderOptions.widths = enrichment::KernelWidths{s.sigmaRho, s.sigmaU};
  ev.enricher->setExamples(ev.set, ev.blenderFor(ev.set));
}

json perContact(const std::vector<acquisition::HeldOutCase>& cases, const acquisition::HeldOutScore& score) {
  json out = json::array();
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const acquisition::PlanEntry& c = cases[i].entry;
    const acquisition::InteractionResult& r = cases[i].result;
    const acquisition::ContactScore& s = score.contacts[i];
    const Eigen::VectorXd& w = s.outcome.weights;
    out.push_back({{"point", vec(c.point)}, {"contact", vec(cases[i].contact.point)}, {"depth", c.depth},
                   {"drag", vec(c.drag)}, {"vertices", s.vertices}, {"ratio", s.ratio()},
                   {"coarse_rms", s.coarseRms}, {"enriched_rms", s.enrichedRms}, {"oracle_rms", s.oracleRms},
                   {"own_stamp_rms", s.ownStampRms}, {"coarse_max", s.coarseMax},
                   {"best_gain_factor", s.detailSize > 0.0 ? json(s.bestGain()) : json(nullptr)},
                   {"enriched_max", s.enrichedMax}, {"confidence", s.outcome.confidence},
                   {"weights", std::vector<double>(w.data(), w.data() + w.size())},
                   {"frame_rule", descriptors::toString(s.outcome.description.frameRule)},
                   {"converged", r.converged}, {"coarse_seconds", r.coarseSeconds}, {"fine_seconds", r.fineSeconds},
                   {"enrich_seconds", s.timings.totalSeconds}, {"descriptor_seconds", s.timings.descriptorSeconds},
                   {"blend_seconds", s.timings.blendSeconds}, {"map_seconds", s.timings.mapSeconds}});
  }
  return out;
}

json report(const Evaluation& ev, const std::vector<acquisition::PlanEntry>& contacts, const acquisition::HeldOutScore& score,
            const json& contactsJson) {
  const EvaluateOptions& s = ev.settings;
  const enrichment::ExampleBlender& blender = *ev.enricher->blender();
  json looFit = nullptr;
  if (const enrichment::StampRegression* r = blender.regression())
    looFit = {{"error", r->fit().looError}, {"gain", blender.gain()}, {"error_with_gain", r->fit().gainedError},
              {"regression_sigma_rho", r->fit().sigmaRho}, {"regression_epsilon", r->fit().epsilon}};
  else if (blender.fit())
    looFit = {{"error", blender.fit()->bestError}, {"gain", blender.gain()}, {"error_with_gain", blender.fit()->gainedError}};
  return {{"scene", ev.scene.name}, {"source_scene", ev.source}, {"transfer", ev.source != ev.scene.name},
          {"material_similarity", ev.similarity}, {"stamp_scale", ev.stampScale}, {"transfer_calibration", ev.calibration},
          {"examples", ev.set.examples.size()}, {"example_set", s.set},
          {"contacts", contacts.size()},
          {"held_out", s.contacts.empty() ? json{{"random", s.heldOut}, {"seed", s.seed}} : json{{"file", s.contacts}}},
          {"stamp_radius", ev.options.stampRadius}, {"open_surface", s.open}, {"site_density", ev.densityDescription},
          {"magnitude_aware", !s.correlationOnly}, {"rim_band", s.rimBand}, {"gain", s.gain}, {"lambda", s.lambda},
          {"min_confidence", s.minConfidence}, {"max_weight_norm", s.maxWeightNorm},
          {"surface_vertices", ev.acquisition->fineSurface().vertices.cols()},
          {"blend", enrichment::toString(blender.method())}, {"sigma_rho", blender.widths().sigmaRho},
          {"sigma_u", blender.widths().sigmaU}, {"leave_one_out", looFit},
          {"coarse_rms", score.coarseRms}, {"enriched_rms", score.enrichedRms}, {"ratio", score.ratio()},
          {"mean_ratio", score.meanRatio()}, {"worst_ratio", score.worstRatio()},
          {"oracle_mean_ratio", score.meanOracleRatio()}, {"own_stamp_mean_ratio", score.meanOwnStampRatio()},
          {"gain_given_truth", gainGivenTruth(score)}, {"coarse_max", score.coarseMax}, {"enriched_max", score.enrichedMax},
          {"compute_seconds_per_frame", score.secondsPerFrame}, {"per_contact", contactsJson}};
}

// Per size N: the first N examples scored, with their oracle; the own stamp does not depend on N.
json learningCurve(Evaluation& ev, const std::vector<acquisition::HeldOutCase>& cases, const std::vector<std::size_t>& sizes) {
  json rows = json::array();
  for (const std::size_t n : sizes) {
    examples::ExampleSet prefix = ev.set;
    prefix.examples.resize(n);
    ev.enricher->setExamples(prefix, ev.blenderFor(prefix));
    const acquisition::HeldOutScore score = acquisition::scoreHeldOut(*ev.enricher, cases, ev.settings.repetitions,
                                                                      acquisition::Bounds::Compute);
    json row = summary(score);
    row["examples"] = n;
    row["oracle_mean_ratio"] = score.meanOracleRatio();
    row["own_stamp_mean_ratio"] = score.meanOwnStampRatio();
    row["median_seconds_per_frame"] = score.medianSecondsPerFrame();
    rows.push_back(row);
    std::cerr << "examples " << n << ": mean ratio " << score.meanRatio() << ", worst " << score.worstRatio() << ", oracle "
              << score.meanOracleRatio() << ", own stamp " << score.meanOwnStampRatio() << "\n";
  }
  ev.enricher->setExamples(ev.set, ev.blenderFor(ev.set));
  return rows;
}

// --also-examples: each set scored on the same cases with the same enricher, which must describe contacts as
// the main set does (else its descriptors would not be comparable).
json otherSets(Evaluation& ev, const std::vector<acquisition::HeldOutCase>& cases) {
  json rows = json::array();
  const enrichment::ContactEnricherOptions& main = ev.options;
  for (const std::string& path : ev.settings.alsoSets) {
    const examples::ExampleSet other = examples::loadExampleSet(path);
    const enrichment::ContactEnricherOptions o = enrichment::optionsFor(other, ev.settings.defaults);
    const auto& a = main.descriptors;
    const auto& b = o.descriptors;
    if (a.window.scale != b.window.scale || a.window.cutoff != b.window.cutoff || a.window.quadrature != b.window.quadrature ||
        a.siteOrder != b.siteOrder || a.deformationOrder != b.deformationOrder || main.sampleSpacing != o.sampleSpacing ||
        main.stampRadius != o.stampRadius)
      throw InvalidInputError("--also-examples " + path + ": its descriptors or stamp radius differ from those of " + ev.settings.set);
    const double similarity = other.metadata.provenance ? enrichment::materialSimilarity(other.metadata.provenance->scene, ev.scene) : 1.0;
    if (similarity != ev.similarity) throw InvalidInputError("--also-examples " + path + ": another material than " + ev.settings.set);
    ev.enricher->setExamples(other, ev.blenderFor(other));
    const acquisition::HeldOutScore score = acquisition::scoreHeldOut(*ev.enricher, cases, ev.settings.repetitions,
                                                                      acquisition::Bounds::Compute);
    json row = summary(score);
    row["example_set"] = path;
    row["examples"] = other.examples.size();
    row["oracle_mean_ratio"] = score.meanOracleRatio();
    row["own_stamp_mean_ratio"] = score.meanOwnStampRatio();
    rows.push_back(row);
    std::cerr << path << ": mean ratio " << score.meanRatio() << ", worst " << score.worstRatio() << "\n";
  }
  ev.enricher->setExamples(ev.set, ev.blenderFor(ev.set));
  return rows;
}

// Run time against error: stamp resolutions and Hermite orders of the whole set.
void variantCurves(Evaluation& ev, const std::vector<acquisition::HeldOutCase>& cases, json& out) {
  const int repetitions = ev.settings.repetitions;
  json byResolution = json::array(), byOrder = json::array();
  const int native = ev.set.examples.front().stamp.rows;
  for (int n : {8, 16, 32, 64}) {
    if (n > native) break;
    const examples::ExampleSet reduced = enrichment::withStampResolution(ev.set, n);
    ev.enricher->setExamples(reduced, ev.blenderFor(reduced));
    json entry = summary(acquisition::scoreHeldOut(*ev.enricher, cases, repetitions));
    entry["stamp_resolution"] = n;
    byResolution.push_back(entry);
    std::cerr << "stamp resolution " << n << ": ratio " << entry["ratio"] << "\n";
  }
  const int siteOrders = ev.set.examples.front().rho.lastOrder(), deformationOrders = ev.set.examples.front().mu.lastOrder();
  for (int m = 1; m <= deformationOrders; ++m)
    for (int n = 1; n <= siteOrders; ++n) {  // rho_1 defines the stamping frame
      enrichment::ContactEnricherOptions orderOptions = ev.options;
      orderOptions.descriptors.siteOrder = n;
      orderOptions.descriptors.deformationOrder = m;
      enrichment::ContactEnricher variant = ev.makeEnricher(orderOptions);
      const examples::ExampleSet reduced = enrichment::withHermiteOrders(ev.set, n, m);
      variant.setExamples(reduced, ev.blenderFor(reduced));
      json entry = summary(acquisition::scoreHeldOut(variant, cases, repetitions));
      entry["site_order"] = n;
      entry["deformation_order"] = m;
      byOrder.push_back(entry);
      std::cerr << "orders rho " << n << ", mu " << m << ": ratio " << entry["ratio"] << "\n";
    }
  ev.enricher->setExamples(ev.set, ev.blenderFor(ev.set));
  out["stamp_resolution_curve"] = byResolution;
  out["hermite_order_curve"] = byOrder;
}

// --coarse-bag: the recording's complete interactions, numbered 0.. in plan order (a line the driver skipped
// has no state and is left out, named).
std::optional<acquisition::RecordedCoarse> recordedHeldOut(const Evaluation& ev) {
#ifdef DE_COARSE_BAG
  if (ev.settings.coarseBag.empty()) return std::nullopt;
  // The driver's bag names its plan; a session recorded with the user's own tools takes it from --contacts.
  const acquisition::RecordedCoarse all =
      ev.settings.contacts.empty()
          ? ros_layer::readCoarseBag(ev.settings.coarseBag, ev.acquisition->fineSurface().numVertices())
          : ros_layer::readSessionBag(ev.settings.coarseBag, *ev.acquisition, acquisition::readPlan(ev.settings.contacts));
  acquisition::RecordedCoarse held{all.path, all.simulator, {}, {}};
  for (std::size_t line = 0; line < all.plan.size(); ++line) {
    const auto state = all.settled.find(line);
    if (state == all.settled.end()) {
      std::cerr << "plan line " << line + 1 << " of " << all.path << " has no settled state: left out\n";
      continue;
    }
    held.settled[held.plan.size()] = state->second;
    held.plan.push_back(all.plan[line]);
  }
  std::cerr << "held-out interactions: " << held.plan.size() << " recorded from " << all.simulator << " in " << all.path << "\n";
  return held;
#else
  (void)ev;
  return std::nullopt;  // a build without ROS has no --coarse-bag
#endif
}

// Transfer calibration: fresh contacts of this scene scored with the set's stamps unscaled; the smallest limit
// they allow (transfer_calibration.hpp) replaces the material similarity for everything scored after it.
void calibrate(Evaluation& ev) {
  const EvaluateOptions& s = ev.settings;
  const unsigned seed = s.calibrationSeed.value_or(s.seed + 1);
  const std::vector<acquisition::PlanEntry> entries = acquisition::randomContacts(*ev.acquisition, s.calibrate, seed);
  std::cerr << "calibration contacts: " << entries.size() << " random, seed " << seed << "\n";
  const std::vector<acquisition::HeldOutCase> cases = acquisition::simulateHeldOut(*ev.acquisition, entries, [&](std::size_t i) {
    std::cerr << "[calibration " << i + 1 << "/" << entries.size() << "] simulating coarse and fine...\n";
  });
  enrichment::DetailGain unscaled = ev.options.gain;
  unscaled.stampGain = s.gain;
  ev.enricher->setDetailGain(unscaled);
  const acquisition::TransferCalibration calibration = acquisition::calibrateTransfer(acquisition::scoreHeldOut(*ev.enricher, cases));
  ev.stampScale = calibration.factor;
  ev.options.gain.stampGain = s.gain * ev.stampScale;
  ev.enricher->setDetailGain(ev.options.gain);
  ev.calibration = {{"contacts", entries.size()}, {"seed", seed}, {"limits", calibration.limits}, {"transfer_gain", ev.stampScale}};
  std::cerr << "calibrated transfer gain " << ev.stampScale << " (material similarity " << ev.similarity << ")"
            << (ev.source != ev.scene.name ? ": the node's ~transfer_gain for this set on this scene\n"
                                           : ": the set is this scene's own, where the node applies no ~transfer_gain\n");
}

json evaluate(Evaluation& ev) {
  const EvaluateOptions& s = ev.settings;
  if (s.calibrate > 0 && !s.coarseBag.empty())
    throw InvalidInputError("--calibrate solves the scene's own coarse model: not with --coarse-bag");
  if (s.calibrate > 0 && s.contacts.empty() && s.calibrationSeed == s.seed)
    throw InvalidInputError("--calibration-seed must differ from --seed: the calibration contacts would be the held-out ones");
  prepare(ev);
  if (s.calibrate > 0) calibrate(ev);
  const std::vector<std::size_t> sizes = s.learningCurve.empty() ? std::vector<std::size_t>()
                                                                 : parseSizes(s.learningCurve, ev.set.examples.size());
  const std::optional<acquisition::RecordedCoarse> recorded = recordedHeldOut(ev);
  const auto contacts = recorded          ? recorded->plan
                        : s.contacts.empty() ? acquisition::randomContacts(*ev.acquisition, s.heldOut, s.seed)
                                             : acquisition::readPlan(s.contacts);
  if (!recorded && s.contacts.empty()) std::cerr << "held-out contacts: " << s.heldOut << " random, seed " << s.seed << "\n";
  const std::vector<acquisition::HeldOutCase> cases = acquisition::simulateHeldOut(*ev.acquisition, contacts, [&](std::size_t i) {
    std::cerr << "[" << i + 1 << "/" << contacts.size() << "] simulating " << (recorded ? "fine" : "coarse and fine") << "...\n";
  }, recorded ? &*recorded : nullptr);
  const acquisition::HeldOutScore score = acquisition::scoreHeldOut(*ev.enricher, cases, s.repetitions, acquisition::Bounds::Compute);
  json out = report(ev, contacts, score, perContact(cases, score));
  if (!sizes.empty()) out["learning_curve"] = learningCurve(ev, cases, sizes);
  if (!s.alsoSets.empty()) out["also"] = otherSets(ev, cases);
  if (s.curves) variantCurves(ev, cases, out);
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Held-out error of coarse vs enriched surfaces against the fine simulation, on any scene"};
  Evaluation ev;
  addOptions(app, ev.settings);
  if (const auto exitCode = deformation_enrichment::tools::parseCommandLine(app, argc, argv)) return *exitCode;
  try {
    std::cout << evaluate(ev).dump(2) << std::endl;
  } catch (const std::exception& e) {
    std::cerr << "de_evaluate: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
