// Shape-space benchmarks ([Brandt16 Table 1 / §7]), each next to its baselines in one process:
//  - geodesic finger0 -> finger1 (2046 vertices, $DE_FINGER_DIR or test/data/finger; skipped with a
//    message when absent) with DE_BENCH_GEODESIC_SHAPES
//    shapes (default 8), minimising eq. 4: reduced with the ghost mesh (1250 vertices) vs reduced exact vs
//    full space (Newton); counters: length and path energy (on the full mesh), iterations, evaluations.
//    With DE_BENCH_LARGE=1 also the paper's flow scheme (reduced, eq. 10), which takes minutes.
//    Paper 004: 6.42 s (Java); target here <= 0.5 s.
//  - one smoothing step of a ~15k-vertex, DE_BENCH_FRAMES-frame (default 140) sequence of a noisy bending
//    sheet (DE_BENCH_GRID^2 vertices, default 122^2 = 14884), reduced with the ghost mesh, shapes in
//    parallel, vs the per-vertex Gaussian trajectory filter; with DE_BENCH_LARGE=1 also reduced exact
//    (minutes); and the run's second step, whose averages start from the first step's final models.
//    Paper 004: 2.13 s/step (Java, with a 1252-vertex ghost mesh); target <= 0.3 s.
//  - end-to-end smoothing runs (smoothingRun): a noisy 17-frame MD2 clip and a 5k-vertex bent armadillo,
//    each next to the tuned Gaussian filter.
// Run: bench_shape_space --benchmark_repetitions=3 --benchmark_report_aggregates_only=true. process_cpu_s is
// the CPU time of all threads (with OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1: the work, whatever the load).
#include <benchmark/benchmark.h>

#include <chrono>
#include <ctime>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "../unit/shape_space/real_sequences.hpp"
#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/md2_reader.hpp"
#include "deformation_enrichment/mesh/mesh_io.hpp"
#include "deformation_enrichment/shape_space/blas_threads.hpp"
#include "deformation_enrichment/shape_space/discrete_shells.hpp"
#include "deformation_enrichment/shape_space/geodesic.hpp"
#include "deformation_enrichment/shape_space/shape_sequence.hpp"
#include "deformation_enrichment/shape_space/smoothing_flow.hpp"

namespace ss = deformation_enrichment::shape_space;
namespace dm = deformation_enrichment::mesh;

namespace {

int envInt(const char* name, int fallback) {
  const char* v = std::getenv(name);
  return v ? std::atoi(v) : fallback;
}

// [finger]: $DE_FINGER_DIR, else the shipped test/data/finger (the source dir from this file's path).
std::string fingerDirectory() {
  if (const char* dir = std::getenv("DE_FINGER_DIR")) return dir;
  return (std::filesystem::path(__FILE__).parent_path().parent_path().parent_path() / "test" / "data" / "finger").string();
}

enum class Mode { ReducedGhost, ReducedExact, Full, FlowReduced };

bool large() { return std::getenv("DE_BENCH_LARGE") != nullptr; }

// Seconds of the last ghost-mesh smoothing step (for the filter baseline's ratio).
double& lastSmoothingSeconds() {
  static double seconds = 0.0;
  return seconds;
}

// Seconds of the last reduced exact geodesic (for the threaded-BLAS baseline's ratio).
double& lastGeodesicSeconds() {
  static double seconds = 0.0;
  return seconds;
}

void geodesicCase(benchmark::State& state, Mode mode) {
  if (mode == Mode::FlowReduced && !large()) {
    state.SkipWithError("set DE_BENCH_LARGE=1 (takes minutes)");
    for (auto _ : state) {
    }
    return;
  }
  const std::string directory = fingerDirectory();
  if (!std::filesystem::exists(directory + "/finger0.ply") || !std::filesystem::exists(directory + "/finger1.ply")) {
    state.SkipWithError(("finger meshes not found in " + directory + " (set DE_FINGER_DIR)").c_str());
    for (auto _ : state) {
    }
    return;
  }
  const dm::TriangleMesh a = dm::readTriangleMesh(directory + "/finger0.ply");
  const dm::TriangleMesh b = dm::readTriangleMesh(directory + "/finger1.ply");
  const ss::ShapeSequence ends = ss::makeSequence({a, b}, 2);
  ss::DiscreteShells energy(ends.triangles, ends.numVertices(), ss::DiscreteShellsOptions::hyperelastic());
  ss::GeodesicOptions options;
  options.shapes = envInt("DE_BENCH_GEODESIC_SHAPES", 8);
  options.tau = 1.0;
  options.reduction.reduced = mode != Mode::Full;
  options.reduction.useGhostMesh = mode == Mode::ReducedGhost;
  options.reduction.subspaceDimension = 16;
  options.solver = mode == Mode::FlowReduced ? ss::GeodesicSolver::Flow : ss::GeodesicSolver::PathEnergy;
  if (mode == Mode::FlowReduced) options.enrichmentRounds = 4;  // the flow scheme with 4 enrichment rounds
  // The full path is the reference: Newton converges quadratically, so it is cheap to solve it well past
  // the paper's rule (1e-8 per dof leaves eq. 4 above the reduced minimum on this case).
  if (mode == Mode::Full) options.absoluteFactor = 1e-14;
  options.requireConvergence = false;
  ss::GeodesicResult g;
  const std::clock_t cpuStart = std::clock();
  const auto start = std::chrono::steady_clock::now();
  for (auto _ : state) {
    g = ss::geodesic(energy, ends.triangles, ends.shapes[0], ends.shapes[1], options);
    benchmark::DoNotOptimize(g.length);
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (mode == Mode::ReducedExact) lastGeodesicSeconds() = seconds;
  // CPU time of all threads: on a shared machine less load-dependent than real time.
  state.counters["process_cpu_s"] = double(std::clock() - cpuStart) / CLOCKS_PER_SEC / double(state.iterations());
  // Accuracy against the full-space path of the same run ([Brandt16 §7]: lengths within 0.1 %, shapes by
  // summed L2 distances relative to the summed shape norms).
  static std::vector<Eigen::VectorXd> fullShapes;
  static double fullLength = 0.0, fullSeconds = 0.0;
  if (mode == Mode::Full) {
    fullShapes = g.shapes;
    fullLength = g.length;
    fullSeconds = seconds;
  } else if (fullShapes.size() == g.shapes.size()) {
    state.counters["speedup_vs_full"] = fullSeconds / seconds;
    double distance = 0.0, norm = 0.0;
    for (size_t k = 0; k < g.shapes.size(); ++k) {
      distance += (g.shapes[k] - fullShapes[k]).norm();
      norm += fullShapes[k].norm();
    }
    state.counters["rel_length_vs_full"] = (g.length - fullLength) / fullLength;
    state.counters["rel_shape_distance_vs_full"] = distance / norm;
  }
  state.counters["length"] = g.length;
  state.counters["path_energy"] = g.pathEnergy;
  state.counters["iterations"] = g.iterations;
  state.counters["evaluations"] = g.evaluations;
  state.counters["ghost_vertices"] = double(g.ghostVertices);
  state.counters["converged"] = g.converged ? 1 : 0;
  state.counters["vertices"] = double(ends.numVertices());
  state.counters["shapes"] = options.shapes;
}

// A bumpy sheet bending over time with per-frame noise: the smoothing input.
ss::ShapeSequence bendingSheet(int n, int frames) {
  ss::ShapeSequence seq;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> noise(-0.002, 0.002);
  seq.triangles.resize(3, 2 * (n - 1) * (n - 1));
  int t = 0;
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      const int v = j * n + i;
      seq.triangles.col(t++) << v, v + 1, v + n + 1;
      seq.triangles.col(t++) << v, v + n + 1, v + n;
    }
  for (int f = 0; f < frames; ++f) {
    const double kappa = 0.2 + 2.0 * std::sin(M_PI * f / (frames - 1));
    Eigen::VectorXd x(3 * n * n);
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const double u = double(i) / (n - 1) - 0.5, w = double(j) / (n - 1);
        const double z = 0.1 * std::sin(3 * u) * std::sin(3 * w), theta = kappa * u, r = 1.0 / kappa - z;
        x.segment<3>(3 * (j * n + i)) << r * std::sin(theta) + noise(rng), w + noise(rng), 1.0 / kappa - r * std::cos(theta) + noise(rng);
      }
    seq.shapes.push_back(x);
  }
  return seq;
}

// progressTolerance: each average's progress stopping rule (ReducedAverageOptions; < 0 keeps the default).
// untimedSteps: steps taken before the timed one (from the second step on, each average starts from the model
// its shape's previous average ended with).
void smoothingStep(benchmark::State& state, bool ghost, double progressTolerance, int untimedSteps = 0) {
  if (!ghost && !large()) {
    state.SkipWithError("set DE_BENCH_LARGE=1 (takes minutes)");
    for (auto _ : state) {
    }
    return;
  }
  const ss::ShapeSequence seq = bendingSheet(envInt("DE_BENCH_GRID", 122), envInt("DE_BENCH_FRAMES", 140));
  ss::DiscreteShells energy(seq.triangles, seq.numVertices(), ss::DiscreteShellsOptions::hyperelastic());
  ss::FlowOptions options;
  options.tau = 0.5;
  options.reduction.reduced = true;
  options.reduction.subspaceDimension = envInt("DE_BENCH_SUBSPACE", 16);
  options.reduction.useGhostMesh = ghost;
  options.parallelShapes = true;  // Jacobi update: the shapes of one step are independent
  if (progressTolerance >= 0.0) options.reducedSolver.progressTolerance = progressTolerance;
  std::optional<ss::SmoothingFlow> built;
  try {
    built.emplace(energy, seq, options);  // preprocess (ghost mesh, subspace, preconditioners): not timed
  } catch (const deformation_enrichment::Error& e) {  // e.g. DE_BENCH_SUBSPACE=0
    state.SkipWithError(e.what());
    for (auto _ : state) {
    }
    return;
  }
  ss::SmoothingFlow& flow = *built;
  for (int k = 0; k < untimedSteps; ++k) flow.step();
  const double before = flow.pathEnergy();
  ss::FlowStep step;
  const std::clock_t cpuStart = std::clock();
  const auto start = std::chrono::steady_clock::now();
  for (auto _ : state) {
    step = flow.step();
    benchmark::DoNotOptimize(step.pathEnergy);
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  state.counters["process_cpu_s"] = double(std::clock() - cpuStart) / CLOCKS_PER_SEC / double(state.iterations());
  if (ghost && progressTolerance < 0.0 && untimedSteps == 0) {
    lastSmoothingSeconds() = seconds;  // the ghost case runs first
  } else if (!ghost && lastSmoothingSeconds() > 0.0) {
    state.counters["exact_over_ghost"] = seconds / lastSmoothingSeconds();
  }
  state.counters["path_energy_before"] = before;
  state.counters["path_energy_after"] = flow.pathEnergy();  // full mesh
  state.counters["ghost_vertices"] = double(flow.ghostVertices());
  state.counters["tau"] = step.tau;
  state.counters["solver_iterations"] = step.solverIterations;
  state.counters["seconds_per_shape"] = benchmark::Counter(double(seq.numShapes() - 2), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  state.counters["vertices"] = double(seq.numVertices());
  state.counters["frames"] = double(seq.numShapes());
}

// Baseline: Gaussian filter (sigma = 1 frame, 7 taps) of every vertex trajectory, same sequence.
void gaussianFilterStep(benchmark::State& state) {
  const ss::ShapeSequence seq = bendingSheet(envInt("DE_BENCH_GRID", 122), envInt("DE_BENCH_FRAMES", 140));
  std::vector<Eigen::VectorXd> out = seq.shapes;
  const auto start = std::chrono::steady_clock::now();
  for (auto _ : state) {
    const int m = int(seq.shapes.size());
    for (int i = 1; i + 1 < m; ++i) {
      Eigen::VectorXd sum = Eigen::VectorXd::Zero(seq.shapes[0].size());
      double weight = 0.0;
      for (int j = std::max(0, i - 3); j <= std::min(m - 1, i + 3); ++j) {
        const double w = std::exp(-0.5 * (i - j) * (i - j));
        sum += w * seq.shapes[size_t(j)];
        weight += w;
      }
      out[size_t(i)] = sum / weight;
    }
    benchmark::DoNotOptimize(out.back().data());
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() / double(state.iterations());
  if (lastSmoothingSeconds() > 0.0) state.counters["ghost_step_over_filter"] = lastSmoothingSeconds() / seconds;
  state.counters["vertices"] = double(seq.numVertices());
  state.counters["frames"] = double(seq.numShapes());
}

// End-to-end smoothing runs of real captures as de_smooth runs them (10 steps, reduced, tau 0.5, restoring
// force 0.05, GOAST's energy for the size) next to the Gaussian trajectory filter tuned to the same
// intrinsic roughness (its one filtering pass timed; the tuning not): a noisy 17-frame MD2 clip (faerie
// taunt, 0.4 % noise) and the stand-in for a 5k-vertex scanned bending sequence (the armadillo of
// [CGAL-data] simplified to 5000 vertices, bent over 16 frames, 0.2 % noise; 1250-vertex ghost mesh).
void smoothingRun(benchmark::State& state, bool md2) {
  namespace st = ss::test;
  ss::ShapeSequence input;
  try {
    if (md2) {
      const dm::Md2Animation animation = dm::readMd2(std::string(st::kMd2Directory) + "faerie.md2");
      input = st::noisyClip(animation, st::Clip{"taunt", 95, 111}, 0.004, 1);
    } else {
      const dm::TriangleMesh armadillo = st::simplified(st::cgalMesh("armadillo"), 5000);
      input = ss::ShapeSequence{armadillo.triangles, st::withNoise(st::bentSequence(armadillo, 16, 1.5), 0.002, 2)};
    }
  } catch (const deformation_enrichment::Error& e) {
    state.SkipWithError(e.what());
    for (auto _ : state) {
    }
    return;
  }
  ss::FlowOptions options = st::captureSmoothing();
  options.parallelShapes = true;
  st::FilterComparison c;
  for (auto _ : state) {
    c = st::compareWithFilter(input, options, 10);
    benchmark::DoNotOptimize(c.smoothed.back().data());
  }
  state.counters["flow_s"] = c.flowSeconds;
  state.counters["filter_s"] = c.filterSeconds;
  state.counters["flow_over_filter"] = c.flowSeconds / c.filterSeconds;
  state.counters["accepted_steps"] = c.accepted;
  state.counters["path_energy_before"] = c.pathEnergy.front();
  state.counters["path_energy_after"] = c.pathEnergy.back();
  state.counters["monotone"] = c.monotone ? 1 : 0;
  state.counters["roughness_ratio"] = c.roughnessAfter / c.roughnessBefore;
  state.counters["trajectory_roughness_ratio"] = c.trajectoryAfter / c.trajectoryBefore;
  state.counters["filter_sigma"] = c.filterTuning.sigma;
  state.counters["filter_reaches_flow"] = c.filterTuning.reached ? 1 : 0;
  state.counters["compared_step"] = c.comparedStep;
  state.counters["edge_change_flow"] = c.flow.edge;
  state.counters["edge_change_filter"] = c.filter.edge;
  state.counters["volume_change_flow"] = c.flow.volume;
  state.counters["volume_change_filter"] = c.filter.volume;
  state.counters["vertices"] = double(input.numVertices());
  state.counters["frames"] = double(input.numShapes());
}

// Baseline of the tools' BLAS choice (blas_threads.hpp): a case run with OpenBLAS's own default, one thread
// per core, as the tools ran before, next to the same case with the single-threaded BLAS that main()
// chooses. `seconds` is where the case records its timed seconds (restored afterwards: it holds the
// single-threaded figure other ratios use). Skipped with another BLAS (the choice changes nothing there).
template <class Case>
void withThreadedBlas(benchmark::State& state, Case run, double& seconds) {
  const int before = ss::openBlasThreads();
  const int cores = int(std::thread::hardware_concurrency());
  if (before == 0 || cores < 2) {
    state.SkipWithError("the BLAS is not OpenBLAS, or one core: nothing to compare");
    for (auto _ : state) {
    }
    return;
  }
  const double single = seconds;
  ss::setOpenBlasThreads(cores);
  run(state);
  ss::setOpenBlasThreads(before);
  state.counters["blas_threads"] = cores;
  if (single > 0.0) state.counters["threaded_over_single_blas"] = seconds / single;
  seconds = single;
}

void geodesicThreadedBlas(benchmark::State& state) {
  withThreadedBlas(state, [](benchmark::State& s) { geodesicCase(s, Mode::ReducedExact); }, lastGeodesicSeconds());
}

void smoothingStepThreadedBlas(benchmark::State& state) {
  withThreadedBlas(state, [](benchmark::State& s) { smoothingStep(s, true, -1.0); }, lastSmoothingSeconds());
}

}  // namespace

// The full-space case runs first: the reduced ones report their distance to its path.
BENCHMARK_CAPTURE(geodesicCase, full, Mode::Full)->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(geodesicCase, reduced_exact, Mode::ReducedExact)->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(geodesicThreadedBlas)->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(geodesicCase, reduced_ghost, Mode::ReducedGhost)->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(geodesicCase, flow_reduced, Mode::FlowReduced)->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();
BENCHMARK_CAPTURE(smoothingStep, reduced_ghost, true, -1.0)->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(smoothingStepThreadedBlas)->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime();
// The second step of the same run (the first untimed): as every step of a run after the first.
BENCHMARK_CAPTURE(smoothingStep, reduced_ghost_second_step, true, -1.0, 1)->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime();
// The same step with each average solved to the decrement rule 1e-12 objective(start) alone (no progress rule).
BENCHMARK_CAPTURE(smoothingStep, reduced_ghost_no_progress_rule, true, 0.0)->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(smoothingStep, reduced_exact, false, -1.0)->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();
BENCHMARK(gaussianFilterStep)->Iterations(3)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(smoothingRun, md2_faerie_taunt_17_frames, true)->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(smoothingRun, armadillo_5k_bent_16_frames, false)->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime();

// As the shape-space tools do at start-up (blas_threads.hpp); the *ThreadedBlas cases are the baseline.
int main(int argc, char** argv) {
  ss::preferSingleThreadedBlas();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
