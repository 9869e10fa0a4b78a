// PSD projection of the Stable Neo-Hookean Hessian: analytic eigensystem ([Smith18 §4]) vs the
// numerical baseline (exact Hessian + Eigen SelfAdjointEigenSolver<9x9> + clamp + rebuild), over the
// same pre-generated random deformation gradients, with and without the rotation-variant SVD; plus the
// two building blocks against their Eigen counterparts (SVD, symmetric 3x3 eigensolver).
//
//   bench_snh_projection [--elements=N] [--distribution=uniform|rest] [google-benchmark flags]
//   e.g. --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
// uniform: entries i.i.d. in [-2, 2] (about half inverted, most Hessians indefinite);
// rest:    F = I + N(0, 0.3^2) per entry (typical simulation states, mostly positive definite).
#include <benchmark/benchmark.h>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <Eigen/SVD>
#include <cstdio>
#include <cstring>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "deformation_enrichment/elasticity/rotation_variant_svd.hpp"
#include "deformation_enrichment/elasticity/stable_neo_hookean.hpp"
#include "deformation_enrichment/elasticity/symmetric_eigen3.hpp"

using namespace deformation_enrichment::elasticity;

namespace {

long gElements = 1000000;
std::string gDistribution = "uniform";

struct Workload {
  std::vector<Eigen::Matrix3d> F;
  std::vector<RotationVariantSvd> svd;
  double fractionIndefinite = 0.0;
};

const StableNeoHookean& material() {
  static const StableNeoHookean snh(1.0, 10.0, SnhVariant::Paper);
  return snh;
}

const Workload& workload() {
  static const Workload w = [] {
    Workload out;
    std::mt19937_64 rng(2018);
    std::uniform_real_distribution<double> entry(-2.0, 2.0);
    std::normal_distribution<double> noise(0.0, 0.3);
    out.F.resize(static_cast<size_t>(gElements));
    for (Eigen::Matrix3d& F : out.F) {
      if (gDistribution == "rest") {
        F = Eigen::Matrix3d::Identity();
        for (int e = 0; e < 9; ++e) F.data()[e] += noise(rng);
      } else {
        for (int e = 0; e < 9; ++e) F.data()[e] = entry(rng);
      }
    }
    out.svd.reserve(out.F.size());
    long indefinite = 0;
    for (const Eigen::Matrix3d& F : out.F) {
      out.svd.push_back(rotationVariantSvd(F));
      if (material().eigensystem(F).values.minCoeff() < 0.0) ++indefinite;
    }
    out.fractionIndefinite = static_cast<double>(indefinite) / static_cast<double>(out.F.size());
    return out;
  }();
  return w;
}

void setCounters(benchmark::State& state) {
  const double n = static_cast<double>(workload().F.size()) * static_cast<double>(state.iterations());
  state.counters["ns_per_element"] = benchmark::Counter(n * 1e-9, benchmark::Counter::kIsRate |
                                                                      benchmark::Counter::kInvert);
  state.counters["indefinite_fraction"] = workload().fractionIndefinite;
}

// Baseline: exact Hessian, 9x9 numerical eigendecomposition, clamp, rebuild.
void BM_NumericalEigen9x9(benchmark::State& state) {
  const Workload& w = workload();
  const StableNeoHookean& snh = material();
  for (auto _ : state) {
    for (const Eigen::Matrix3d& F : w.F) {
      const Eigen::SelfAdjointEigenSolver<Matrix9d> eig(snh.hessian(F));
      const Vector9d clamped = eig.eigenvalues().cwiseMax(0.0);
      Matrix9d H = eig.eigenvectors() * clamped.asDiagonal() * eig.eigenvectors().transpose();
      benchmark::DoNotOptimize(H.data());
    }
  }
  setCounters(state);
}

void BM_AnalyticIncludingSvd(benchmark::State& state) {
  const Workload& w = workload();
  const StableNeoHookean& snh = material();
  for (auto _ : state) {
    for (const Eigen::Matrix3d& F : w.F) {
      Matrix9d H = snh.projectedHessian(F);
      benchmark::DoNotOptimize(H.data());
    }
  }
  setCounters(state);
}

void BM_AnalyticExcludingSvd(benchmark::State& state) {
  const Workload& w = workload();
  const StableNeoHookean& snh = material();
  for (auto _ : state) {
    for (size_t e = 0; e < w.F.size(); ++e) {
      Matrix9d H = snh.projectedHessian(w.F[e], w.svd[e]);
      benchmark::DoNotOptimize(H.data());
    }
  }
  setCounters(state);
}

void BM_RotationVariantSvd(benchmark::State& state) {
  const Workload& w = workload();
  for (auto _ : state) {
    for (const Eigen::Matrix3d& F : w.F) {
      RotationVariantSvd svd = rotationVariantSvd(F);
      benchmark::DoNotOptimize(svd.U.data());
    }
  }
  setCounters(state);
}

// Baseline for the SVD: Eigen's two-sided JacobiSVD plus the same reflection fix-up.
void BM_EigenJacobiSvd(benchmark::State& state) {
  const Workload& w = workload();
  for (auto _ : state) {
    for (const Eigen::Matrix3d& F : w.F) {
      const Eigen::JacobiSVD<Eigen::Matrix3d> svd(F, Eigen::ComputeFullU | Eigen::ComputeFullV);
      Eigen::Matrix3d U = svd.matrixU(), V = svd.matrixV();
      Eigen::Vector3d sigma = svd.singularValues();
      if (U.determinant() < 0.0) U.col(2) *= -1.0, sigma(2) *= -1.0;
      if (V.determinant() < 0.0) V.col(2) *= -1.0, sigma(2) *= -1.0;
      benchmark::DoNotOptimize(U.data());
      benchmark::DoNotOptimize(V.data());
      benchmark::DoNotOptimize(sigma.data());
    }
  }
  setCounters(state);
}

// The 3x3 symmetric eigensolver of the scaling block: closed form vs Eigen's iterative solver, on the
// symmetric parts (F + F^T) / 2 of the workload (indefinite, like the scaling blocks).
void BM_SymmetricEigen3(benchmark::State& state) {
  const Workload& w = workload();
  for (auto _ : state) {
    for (const Eigen::Matrix3d& F : w.F) {
      SymmetricEigen3 eig = symmetricEigen3(0.5 * (F + F.transpose()));
      benchmark::DoNotOptimize(eig.vectors.data());
    }
  }
  setCounters(state);
}

void BM_EigenSelfAdjoint3(benchmark::State& state) {
  const Workload& w = workload();
  for (auto _ : state) {
    for (const Eigen::Matrix3d& F : w.F) {
      const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(0.5 * (F + F.transpose()));
      benchmark::DoNotOptimize(eig.eigenvectors().data());
    }
  }
  setCounters(state);
}

BENCHMARK(BM_NumericalEigen9x9)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(BM_AnalyticIncludingSvd)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(BM_AnalyticExcludingSvd)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(BM_RotationVariantSvd)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(BM_EigenJacobiSvd)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(BM_SymmetricEigen3)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(BM_EigenSelfAdjoint3)->Unit(benchmark::kMillisecond)->Iterations(1);

// Console output plus the median CPU time of each benchmark (robust to the shared machine's load), for the ratios printed at the end.
class RatioReporter : public benchmark::ConsoleReporter {
public:
  void ReportRuns(const std::vector<Run>& runs) override {
    ConsoleReporter::ReportRuns(runs);
    for (const Run& run : runs) {
      const std::string name = run.benchmark_name();
      const bool isMedian = run.run_type == Run::RT_Aggregate && run.aggregate_name == "median";
      if (run.run_type == Run::RT_Iteration || isMedian) {
        const std::string base = name.substr(0, name.find('/'));
        // Medians override single runs when repetitions are requested.
        if (isMedian || medians_.count(base) == 0) medians_[base] = run.GetAdjustedCPUTime();
      }
    }
  }
  void printRatios() const {
    for (const char* name : {"BM_NumericalEigen9x9", "BM_AnalyticIncludingSvd", "BM_AnalyticExcludingSvd",
                             "BM_RotationVariantSvd", "BM_EigenJacobiSvd", "BM_SymmetricEigen3",
                             "BM_EigenSelfAdjoint3"}) {
      if (medians_.count(name) == 0) return;  // filtered out: no ratios to print
    }
    const double n = static_cast<double>(gElements);
    auto nsPerElement = [&](const char* name) { return medians_.at(name) * 1e6 / n; };  // ms -> ns
    const double numerical = nsPerElement("BM_NumericalEigen9x9");
    const double including = nsPerElement("BM_AnalyticIncludingSvd");
    const double excluding = nsPerElement("BM_AnalyticExcludingSvd");
    const double svd = nsPerElement("BM_RotationVariantSvd");
    const double eigenSvd = nsPerElement("BM_EigenJacobiSvd");
    std::printf("\n%ld elements, distribution '%s', indefinite fraction %.3f\n", gElements,
                gDistribution.c_str(), workload().fractionIndefinite);
    std::printf("median CPU ns/element: numerical 9x9 %.1f | analytic incl. SVD %.1f | analytic excl. SVD %.1f\n",
                numerical, including, excluding);
    std::printf("rotation-variant SVD: one-sided Jacobi %.1f | Eigen JacobiSVD %.1f (%.2fx)\n", svd, eigenSvd,
                eigenSvd / svd);
    const double eig3 = nsPerElement("BM_SymmetricEigen3");
    const double eigenEig3 = nsPerElement("BM_EigenSelfAdjoint3");
    std::printf("symmetric 3x3 eigen: closed form %.1f | Eigen SelfAdjointEigenSolver %.1f (%.2fx)\n", eig3,
                eigenEig3, eigenEig3 / eig3);
    std::printf("speed-up over numerical: %.2fx including SVD, %.2fx excluding SVD\n", numerical / including,
                numerical / excluding);
  }

private:
  std::map<std::string, double> medians_;
};

}  // namespace

int main(int argc, char** argv) {
  std::vector<char*> rest;
  for (int i = 0; i < argc; ++i) {
    if (std::strncmp(argv[i], "--elements=", 11) == 0) {
      gElements = std::stol(argv[i] + 11);
    } else if (std::strncmp(argv[i], "--distribution=", 15) == 0) {
      gDistribution = argv[i] + 15;
    } else {
      rest.push_back(argv[i]);
    }
  }
  if (gElements <= 0 || (gDistribution != "uniform" && gDistribution != "rest")) {
    std::fprintf(stderr, "usage: %s [--elements=N>0] [--distribution=uniform|rest] [benchmark flags]\n", argv[0]);
    return 2;
  }
  int restArgc = static_cast<int>(rest.size());
  benchmark::Initialize(&restArgc, rest.data());
  workload();  // generate outside any timing
  RatioReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  reporter.printRatios();
  benchmark::Shutdown();
  return 0;
}
