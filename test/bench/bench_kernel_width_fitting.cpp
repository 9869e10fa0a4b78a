// Kernel-width fitting by leave-one-out ([Seiler14 §5], "finished in a few seconds"; target: seconds for
// 100 examples). Groups:
//   LooError/GramDowndate vs LooError/Explicit: one width pair's leave-one-out error over N examples with
//     64x64 stamps, as fitKernelWidths computes it (stamp Gram matrix, (K_S)^2 from one K^2) vs the
//     literal procedure (per held-out example: sub-table, dissimilarities, RbfInterpolator, correlate,
//     blendStamps, stamp difference).
//   Fit/Grid12x12: the whole 144-pair brute force (default grid), N = 100, Gram matrix included.
#include <benchmark/benchmark.h>

#include <map>
#include <memory>
#include <random>

#include "deformation_enrichment/enrichment/kernel_width_fitting.hpp"
#include "deformation_enrichment/enrichment/stamp_blending.hpp"
#include "ratio_reporter.hpp"

using namespace deformation_enrichment;

namespace {

struct Set {
  std::vector<hermite::MomentList> rho, mu;
  std::vector<cv::Mat> stamps;
  enrichment::ExampleDissimilarities d;
};

const Set& set(int count) {
  static std::map<int, std::unique_ptr<Set>> cache;
  auto& s = cache[count];
  if (s) return *s;
  s = std::make_unique<Set>();
  std::mt19937 rng(count);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int i = 0; i < count; ++i) {
    // Stamps vary smoothly with a 2D site parameter and a deformation angle, as a real set would.
    const double t0 = u(rng), t1 = u(rng), theta = 1.5 * u(rng);
    hermite::MomentList rho(0, 3, 1), mu(1, 2, 3);
    rho.values().setZero();
    mu.values().setZero();
    rho.values()[0] = t0;
    rho.values()[1] = t1;
    mu.values()[0] = std::cos(theta);
    mu.values()[1] = std::sin(theta);
    cv::Mat stamp(64, 64, CV_32FC3);
    for (int j = 0; j < 64; ++j)
      for (int k = 0; k < 64; ++k)
        stamp.at<cv::Vec3f>(j, k) = cv::Vec3f(float(std::sin(0.1 * k + 3 * t0) * std::cos(0.1 * j + theta)), float(t1 * std::cos(0.05 * k)),
                                              float(std::sin(theta + 0.1 * j)));
    s->rho.push_back(rho);
    s->mu.push_back(mu);
    s->stamps.push_back(stamp);
  }
  const enrichment::ExampleDescriptorTable table(s->rho, s->mu);
  s->d = enrichment::exampleDissimilarities(table, s->rho, s->mu);
  return *s;
}

const enrichment::KernelWidths kWidths{0.3, 0.3};

void BM_LooGram(benchmark::State& state) {
  const Set& s = set(static_cast<int>(state.range(0)));
  const Eigen::MatrixXd G = enrichment::stampGramMatrix(s.stamps);
  double error = 0.0;
  for (auto _ : state) benchmark::DoNotOptimize(error = enrichment::leaveOneOutError(s.d, G, kWidths));
  state.counters["error"] = error;
}

void BM_LooExplicit(benchmark::State& state) {
  const Set& s = set(static_cast<int>(state.range(0)));
  double result = 0.0;
  for (auto _ : state) {
    double error = 0.0, norm = 0.0;
    for (std::size_t k = 0; k < s.stamps.size(); ++k) {
      std::vector<hermite::MomentList> rho, mu;
      std::vector<cv::Mat> stamps;
      for (std::size_t i = 0; i < s.stamps.size(); ++i)
        if (i != k) {
          rho.push_back(s.rho[i]);
          mu.push_back(s.mu[i]);
          stamps.push_back(s.stamps[i]);
        }
      const enrichment::ExampleDescriptorTable table(rho, mu);
      const enrichment::RbfInterpolator rbf(enrichment::kernelMatrix(enrichment::exampleDissimilarities(table, rho, mu), kWidths));
      enrichment::Correlation c;
      enrichment::correlate(table, s.rho[k], s.mu[k], kWidths, c);
      enrichment::RbfWeights w;
      rbf.interpolate(c.weights, w);
      cv::Mat diff;
      cv::subtract(enrichment::blendStamps(stamps, w.weights), s.stamps[k], diff, cv::noArray(), CV_64FC3);
      error += diff.dot(diff);
      cv::Mat exact;
      s.stamps[k].convertTo(exact, CV_64FC3);
      norm += exact.dot(exact);
    }
    benchmark::DoNotOptimize(result = error / norm);
  }
  state.counters["error"] = result;
}

void BM_FitGrid(benchmark::State& state) {
  const Set& s = set(static_cast<int>(state.range(0)));
  enrichment::KernelWidthFit fit;
  for (auto _ : state) {
    fit = enrichment::fitKernelWidths(s.d, enrichment::stampGramMatrix(s.stamps), enrichment::defaultKernelWidthGrid(s.d, 12));
    benchmark::DoNotOptimize(fit.bestError);
  }
  state.counters["best_error"] = fit.bestError;
  state.counters["sigma_rho"] = fit.best.sigmaRho;
  state.counters["sigma_u"] = fit.best.sigmaU;
}

}  // namespace

BENCHMARK(BM_LooGram)->Name("LooError/GramDowndate")->Arg(10)->Arg(100)->ArgName("examples")->Unit(benchmark::kMillisecond);
BENCHMARK(BM_LooExplicit)->Name("LooError/Explicit")->Arg(10)->Arg(100)->ArgName("examples")->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FitGrid)->Name("Fit/Grid12x12")->Arg(100)->ArgName("examples")->Unit(benchmark::kMillisecond)->Iterations(1);

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  de_bench::RatioReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  reporter.printRatios("GramDowndate", "Explicit");
  benchmark::Shutdown();
  return 0;
}
