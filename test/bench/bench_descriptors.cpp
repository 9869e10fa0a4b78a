// Descriptor evaluation at a contact ([Seiler14 §4]) on point sets of 10k / 100k / 1M samples of the unit
// cube, orders N = 1..4: window gathered by the KD-tree (built once per mesh) vs a brute-force scan over
// all samples, side by side; plus the full contact (rho N=3, frame, MLS + mu N=2) with the KD-tree.
// Fixed window h = 0.05 m (cut-off 0.2 m) on the top face: finer meshes put more samples in the window.
#include <benchmark/benchmark.h>

#include <map>
#include <memory>

#include "deformation_enrichment/descriptors/deformation_descriptor.hpp"
#include "deformation_enrichment/descriptors/moment_window.hpp"
#include "deformation_enrichment/descriptors/stamping_frame.hpp"
#include "ratio_reporter.hpp"

using namespace deformation_enrichment;
using namespace deformation_enrichment::descriptors;

namespace {
constexpr double kScale = 0.05;
const Eigen::Vector3d kContact(0.503, 0.497, 1.0);

// n^3 grid samples of [0,1]^3 with cell volumes (what lumping gives in the interior of a uniform mesh).
const PointSampling& sampling(int pointsPerAxis) {
  static std::map<int, std::unique_ptr<PointSampling>> cache;
  auto& entry = cache[pointsPerAxis];
  if (!entry) {
    const int n = pointsPerAxis;
    Eigen::Matrix3Xd points(3, static_cast<Eigen::Index>(n) * n * n);
    const double step = 1.0 / (n - 1);
    Eigen::Index m = 0;
    for (int k = 0; k < n; ++k)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) points.col(m++) = Eigen::Vector3d(i, j, k) * step;
    entry = std::make_unique<PointSampling>(points, Eigen::VectorXd::Constant(points.cols(), step * step * step));
  }
  return *entry;
}

int axisPoints(int64_t total) { return total == 10000 ? 22 : total == 100000 ? 47 : 100; }

void siteDescriptor(benchmark::State& state, NeighbourSearch search) {
  const PointSampling& samples = sampling(axisPoints(state.range(0)));
  const int order = static_cast<int>(state.range(1));
  WindowOptions options;
  options.scale = kScale;
  options.search = search;
  std::size_t windowSize = 0;
  for (auto _ : state) {
    const Window window = gatherWindow(samples, kContact, options);
    hermite::MomentList rho = densityMoments(window, 0, order);
    benchmark::DoNotOptimize(rho.values().data());
    windowSize = window.indices.size();
  }
  state.counters["samples"] = static_cast<double>(samples.size());
  state.counters["window"] = static_cast<double>(windowSize);
}

void BM_Site_KdTree(benchmark::State& state) { siteDescriptor(state, NeighbourSearch::KdTree); }
void BM_Site_BruteForce(benchmark::State& state) { siteDescriptor(state, NeighbourSearch::BruteForce); }

void contact(benchmark::State& state, NeighbourSearch search) {
  const PointSampling& samples = sampling(axisPoints(state.range(0)));
  WindowOptions options;
  options.scale = kScale;
  options.search = search;
  // A smooth indentation of the top face as the deformed state.
  Eigen::Matrix3Xd deformed = samples.points();
  for (Eigen::Index m = 0; m < deformed.cols(); ++m) {
    const Eigen::Vector3d d = samples.points().col(m) - kContact;
    deformed(2, m) -= 0.01 * std::exp(-d.squaredNorm() / (2 * 0.04 * 0.04));
  }
  const Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  for (auto _ : state) {
    const Window window = gatherWindow(samples, kContact, options);
    const hermite::MomentList rho = densityMoments(window, 0, 3);
    const DeformationDescriptor mu = deformationDescriptor(window, samples.points(), deformed, 2, &normal, &normal);
    const StampingFrame frame = stampingFrame(normal, rho, &mu.mu);
    const hermite::MomentList muFrame = mu.mu.transformed(frame.B.transpose());
    benchmark::DoNotOptimize(muFrame.values().data());
  }
  state.counters["samples"] = static_cast<double>(samples.size());
}
void BM_Contact_KdTree(benchmark::State& state) { contact(state, NeighbourSearch::KdTree); }
void BM_Contact_BruteForce(benchmark::State& state) { contact(state, NeighbourSearch::BruteForce); }

void siteArgs(benchmark::internal::Benchmark* b) {
  for (int64_t points : {10000, 100000, 1000000})
    for (int64_t order = 1; order <= 4; ++order) b->Args({points, order});
  b->ArgNames({"points", "N"})->Unit(benchmark::kMicrosecond);
}
void contactArgs(benchmark::internal::Benchmark* b) {
  for (int64_t points : {10000, 100000, 1000000}) b->Args({points});
  b->ArgNames({"points"})->Unit(benchmark::kMicrosecond);
}
}  // namespace

BENCHMARK(BM_Site_KdTree)->Name("Site/KdTree")->Apply(siteArgs);
BENCHMARK(BM_Site_BruteForce)->Name("Site/BruteForce")->Apply(siteArgs);
BENCHMARK(BM_Contact_KdTree)->Name("Contact/KdTree")->Apply(contactArgs);
BENCHMARK(BM_Contact_BruteForce)->Name("Contact/BruteForce")->Apply(contactArgs);

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  de_bench::RatioReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  reporter.printRatios("KdTree", "BruteForce");
  benchmark::Shutdown();
  return 0;
}
