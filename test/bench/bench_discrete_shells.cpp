// Discrete Shells (hyperelastic membrane + bending) on a ~15k-vertex mesh: value + gradient + Hessian,
// serial (1 thread) against parallel (all OpenMP threads) in one process; prints medians and the ratio.
#include <benchmark/benchmark.h>

#include <iostream>
#include <map>
#include <string>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "../unit/shape_space/shell_test_meshes.hpp"
#include "deformation_enrichment/shape_space/discrete_shells.hpp"

namespace {

using deformation_enrichment::shape_space::DiscreteShells;
using deformation_enrichment::shape_space::DiscreteShellsOptions;
using deformation_enrichment::shape_space::EnergyOutputs;
namespace test = deformation_enrichment::shape_space::test;

constexpr int kGridSide = 122;  // 14884 vertices, 29282 triangles

const test::FlatMesh& benchMesh() {
  static const test::FlatMesh mesh = test::bumpyGrid(kGridSide, 1);
  return mesh;
}

int maxThreads() {
#ifdef _OPENMP
  return omp_get_max_threads();
#else
  return 1;
#endif
}

enum class Request { ValueGradientHessianDeformed, ValueGradientDeformed, All };

void run(benchmark::State& state, Request request) {
  const test::FlatMesh& mesh = benchMesh();
  DiscreteShells energy(mesh.triangles, mesh.vertices.size() / 3, DiscreteShellsOptions::hyperelastic());
  energy.setThreadCount(static_cast<int>(state.range(0)));
  const Eigen::VectorXd deformed = test::perturbed(mesh.vertices, 0.002, 2);
  double value = 0.0;
  Eigen::VectorXd gradientDeformed, gradientReference;
  Eigen::SparseMatrix<double> hessianDeformed, hessianMixed, hessianReference;
  EnergyOutputs outputs;
  outputs.value = &value;
  outputs.gradientDeformed = &gradientDeformed;
  if (request != Request::ValueGradientDeformed) outputs.hessianDeformed = &hessianDeformed;
  if (request == Request::All) {
    outputs.gradientReference = &gradientReference;
    outputs.hessianMixed = &hessianMixed;
    outputs.hessianReference = &hessianReference;
  }
  for (auto _ : state) {
    energy.evaluate(mesh.vertices, deformed, outputs);
    benchmark::DoNotOptimize(value);
  }
  state.counters["vertices"] = static_cast<double>(energy.numVertices());
  state.counters["threads"] = static_cast<double>(state.range(0));
}

void BM_ValueGradientHessianDeformed(benchmark::State& state) {
  run(state, Request::ValueGradientHessianDeformed);
}
void BM_ValueGradientDeformed(benchmark::State& state) {
  run(state, Request::ValueGradientDeformed);
}
void BM_AllBlocks(benchmark::State& state) {
  run(state, Request::All);
}

// Collects the median of every run and prints parallel/serial ratios at the end.
class RatioReporter : public benchmark::ConsoleReporter {
public:
  void ReportRuns(const std::vector<Run>& runs) override {
    ConsoleReporter::ReportRuns(runs);
    for (const Run& run : runs) {
      if (run.run_type == Run::RT_Aggregate && run.aggregate_name == "median") {
        medians_[run.benchmark_name()] = run.GetAdjustedRealTime();
      }
    }
  }
  void Finalize() override {
    ConsoleReporter::Finalize();
    const std::string parallel = "/" + std::to_string(maxThreads()) + "/";
    for (const auto& [name, serialTime] : medians_) {
      const std::size_t slash = name.find("/1/");
      if (slash == std::string::npos) continue;
      const std::string other = name.substr(0, slash) + parallel + name.substr(slash + 3);
      const auto it = medians_.find(other);
      if (it == medians_.end() || other == name) continue;
      std::cout << name.substr(0, slash) << ": serial median " << serialTime << " ms, " << maxThreads()
                << " threads median " << it->second << " ms, speed-up x" << serialTime / it->second << "\n";
    }
  }

private:
  std::map<std::string, double> medians_;
};

}  // namespace

int main(int argc, char** argv) {
  for (auto* bench : {benchmark::RegisterBenchmark("ValueGradientHessianDeformed", BM_ValueGradientHessianDeformed),
                      benchmark::RegisterBenchmark("ValueGradientDeformed", BM_ValueGradientDeformed),
                      benchmark::RegisterBenchmark("AllBlocks", BM_AllBlocks)}) {
    bench->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();
    if (maxThreads() > 1) bench->Arg(maxThreads());
  }
  benchmark::Initialize(&argc, argv);
  RatioReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  benchmark::Shutdown();
  return 0;
}
