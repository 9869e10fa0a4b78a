// Newton solve of one tool indentation (3 mm at the centre, 6 mm tool radius, one load step from rest)
// on the default slab (0.10 x 0.10 x 0.02 m, 1 mm stiff skin over soft bulk) at ~5k / 50k / 200k tets,
// CHOLMOD (supernodal) against Eigen's SimplicialLDLT in the same process. Reports wall time per solve
// (symbolic analysis included), Newton iterations, factorisations, free dofs and the process's peak
// resident memory (ru_maxrss: a running maximum, so run sizes in increasing order). The chord-step reuse
// of factorisations and the conjugate-gradient directions preconditioned by the last factorisation are on by
// default; "cholmod_chord_only" turns the second off (the baseline of the preconditioned directions) and
// "cholmod_no_reuse" is the ablation that factorises every iteration.
// The 200k case runs only with DE_BENCH_LARGE=1 (CHOLMOD only: SimplicialLDLT takes minutes there).
#include <benchmark/benchmark.h>
#include <sys/resource.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <memory>
#include <vector>

#include "deformation_enrichment/elasticity/quasi_static_solver.hpp"
#include "deformation_enrichment/scenes/procedural_scene.hpp"
#include "deformation_enrichment/acquisition/tool_loading.hpp"

using namespace deformation_enrichment;

namespace {

struct Case {
  scenes::Scene scene;
  std::unique_ptr<elasticity::TetFem> fem;
  elasticity::DirichletConstraints constraints;
};

/// Slab with n x n cells in plan and m bulk cells plus one skin layer through the thickness.
const Case& slabCase(int n, int m) {
  static std::map<std::pair<int, int>, std::unique_ptr<Case>> cache;
  auto& entry = cache[{n, m}];
  if (!entry) {
    entry = std::make_unique<Case>();
    scenes::SlabOptions options;
    options.layering.cells = Eigen::Vector3i(n, n, m);
    entry->scene = scenes::makeSlab(options);
    const auto bulk = elasticity::lameFromYoungPoisson(1e4, 0.45);
    const auto skin = elasticity::lameFromYoungPoisson(1e6, 0.3);
    entry->fem = std::make_unique<elasticity::TetFem>(
        entry->scene.mesh,
        std::vector<elasticity::StableNeoHookean>{elasticity::StableNeoHookean(bulk.mu, bulk.lambda),
                                                  elasticity::StableNeoHookean(skin.mu, skin.lambda)},
        entry->scene.materialId);
    const auto tool = acquisition::toolFootprint(entry->scene, Eigen::Vector2d::Zero(), 0.006);
    entry->constraints = acquisition::toolConstraints(entry->scene, tool, Eigen::Vector3d(0, 0, -0.003));
  }
  return *entry;
}

double peakResidentMegabytes() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024.0;  // kilobytes on Linux
}

std::map<std::pair<long, long>, std::vector<double>> wallTimes;  // (tets, solver) -> seconds per solve (defaults)
std::map<long, std::vector<double>> chordOnlyTimes;               // tets -> seconds per solve (CHOLMOD, no CG)

void BM_NewtonIndent(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0)), m = static_cast<int>(state.range(1));
  const auto kind = static_cast<numerics::SparseCholeskyBackend>(state.range(2));
  const Case& c = slabCase(n, m);
  elasticity::SolverOptions settings;
  settings.linearSolver = kind;
  if (state.range(3) == 0) settings.reuseContraction = 0.0;  // ablation: factorise every iteration
  if (state.range(3) != 1) settings.preconditionedTolerance = 0.0;
  elasticity::SolveResult result;
  for (auto _ : state) {
    elasticity::QuasiStaticSolver solver(*c.fem, settings);  // fresh: symbolic analysis is part of the cost
    Eigen::Matrix3Xd x = c.scene.mesh.vertices;
    result = solver.solve(x, c.constraints);
    benchmark::DoNotOptimize(x.data());
    if (state.range(3) == 1) wallTimes[{c.fem->numTets(), state.range(2)}].push_back(result.seconds);
    if (state.range(3) == 2) chordOnlyTimes[c.fem->numTets()].push_back(result.seconds);
  }
  if (!result.converged()) state.SkipWithError(result.message.c_str());
  state.counters["tets"] = static_cast<double>(c.fem->numTets());
  state.counters["free_dofs"] = result.freeDofs;
  state.counters["newton_iterations"] = result.iterations;
  state.counters["factorizations"] = result.factorizations;
  state.counters["peak_rss_MB"] = peakResidentMegabytes();
  double factor = 0.0, assembly = 0.0;
  for (const auto& record : result.history) {
    factor += record.factorSeconds;
    assembly += record.assemblySeconds;
  }
  state.counters["factor_solve_s"] = factor;
  state.counters["assembly_s"] = assembly;
}

constexpr long kCholmod = static_cast<long>(numerics::SparseCholeskyBackend::Cholmod);
constexpr long kLdlt = static_cast<long>(numerics::SparseCholeskyBackend::EigenSimplicial);

void registerCases() {
  const std::vector<std::pair<int, int>> sizes{{15, 3}, {32, 7}};  // 5400 and 49152 tets
  for (const auto& size : sizes) {
#ifdef DE_HAVE_CHOLMOD
    benchmark::RegisterBenchmark("NewtonIndent/cholmod", BM_NewtonIndent)
        ->Args({size.first, size.second, kCholmod, 1})->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();
    benchmark::RegisterBenchmark("NewtonIndent/cholmod_chord_only", BM_NewtonIndent)
        ->Args({size.first, size.second, kCholmod, 2})->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();
    benchmark::RegisterBenchmark("NewtonIndent/cholmod_no_reuse", BM_NewtonIndent)
        ->Args({size.first, size.second, kCholmod, 0})->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();
#endif
    benchmark::RegisterBenchmark("NewtonIndent/simplicial_ldlt", BM_NewtonIndent)
        ->Args({size.first, size.second, kLdlt, 1})->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();
  }
#ifdef DE_HAVE_CHOLMOD
  if (std::getenv("DE_BENCH_LARGE")) {  // 194688 tets
    benchmark::RegisterBenchmark("NewtonIndent/cholmod", BM_NewtonIndent)
        ->Args({52, 11, kCholmod, 1})->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();
    benchmark::RegisterBenchmark("NewtonIndent/cholmod_chord_only", BM_NewtonIndent)
        ->Args({52, 11, kCholmod, 2})->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();
  }
#endif
}

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const std::size_t k = values.size() / 2;
  return values.size() % 2 ? values[k] : 0.5 * (values[k - 1] + values[k]);
}

}  // namespace

int main(int argc, char** argv) {
  registerCases();
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  std::printf("\nmedian wall time per indentation solve (s):\n%10s %12s %12s %12s %10s\n", "tets", "cholmod", "chord only",
              "ldlt", "ldlt/chol");
  std::map<long, std::pair<double, double>> table;
  for (const auto& [key, times] : wallTimes) {
    auto& row = table[key.first];
    (key.second == kCholmod ? row.first : row.second) = median(times);
  }
  for (const auto& [tets, row] : table) {
    const double chord = chordOnlyTimes.count(tets) ? median(chordOnlyTimes[tets]) : 0.0;
    std::printf("%10ld %12.3f %12.3f %12.3f %10.2f\n", tets, row.first, chord, row.second,
                row.first > 0 && row.second > 0 ? row.second / row.first : 0.0);
  }
  benchmark::Shutdown();
  return 0;
}
