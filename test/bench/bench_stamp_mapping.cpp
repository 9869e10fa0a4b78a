// Per-frame enrichment of a 50k-vertex surface (target: <= 1 ms compute with 10 examples).
// Groups:
//   Mapping/KdTree vs Mapping/BruteForce: the eq. (1) displacement mapping of one blended 64x64 stamp,
//     StampMapper (nanoflann ball query on the rest surface) vs a scan of every vertex.
//   Frame/Enrich vs Frame/Copy: the whole run-time chain for one contact (eq. 15 correlate with 10
//     examples, RBF interpolation, eq. 16 blending of 64x64 stamps, mapping, s + e applied to a copy of
//     the state) vs the floor of only copying the state.
#include <benchmark/benchmark.h>

#include <Eigen/Geometry>
#include <cmath>
#include <algorithm>
#include <map>
#include <memory>
#include <random>

#include "deformation_enrichment/enrichment/blending_weights.hpp"
#include "deformation_enrichment/enrichment/rbf_interpolation.hpp"
#include "deformation_enrichment/enrichment/stamp.hpp"
#include "deformation_enrichment/enrichment/stamp_blending.hpp"
#include "ratio_reporter.hpp"

using namespace deformation_enrichment;

namespace {

struct Scene {
  Eigen::Matrix3Xd rest;
  std::vector<hermite::MomentList> rho, mu;
  std::vector<cv::Mat> stamps;
  std::unique_ptr<enrichment::ExampleDescriptorTable> table;
  std::unique_ptr<enrichment::RbfInterpolator> rbf;
  std::unique_ptr<enrichment::StampMapper> mapper;
  enrichment::ContactStamp contact;
};

const enrichment::KernelWidths kWidths{1.0, 0.5};

Scene& scene(int vertices) {
  static std::map<int, std::unique_ptr<Scene>> cache;
  auto& s = cache[vertices];
  if (s) return *s;
  s = std::make_unique<Scene>();
  const int n = static_cast<int>(std::round(std::sqrt(double(vertices))));
  s->rest.resize(3, n * n);
  for (int j = 0; j < n; ++j)
    for (int k = 0; k < n; ++k) s->rest.col(j * n + k) = Eigen::Vector3d(-0.05 + 0.1 * k / (n - 1), -0.05 + 0.1 * j / (n - 1), 0.02);
  std::mt19937 rng(1);
  std::normal_distribution<double> normal;
  for (int i = 0; i < 10; ++i) {
    hermite::MomentList rho(0, 3, 1), mu(1, 2, 3);
    for (Eigen::Index k = 0; k < rho.values().size(); ++k) rho.values()[k] = normal(rng);
    for (Eigen::Index k = 0; k < mu.values().size(); ++k) mu.values()[k] = normal(rng);
    s->rho.push_back(rho);
    s->mu.push_back(mu);
    cv::Mat stamp(64, 64, CV_32FC3);
    cv::randn(stamp, cv::Scalar::all(0.0), cv::Scalar::all(1e-3));
    s->stamps.push_back(stamp);
  }
  s->table = std::make_unique<enrichment::ExampleDescriptorTable>(s->rho, s->mu);
  s->rbf = std::make_unique<enrichment::RbfInterpolator>(
      enrichment::kernelMatrix(enrichment::exampleDissimilarities(*s->table, s->rho, s->mu), kWidths));
  s->mapper = std::make_unique<enrichment::StampMapper>(s->rest);
  s->contact.contact = Eigen::Vector3d(0.003, -0.002, 0.02);
  s->contact.frame = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  s->contact.rotation = Eigen::AngleAxisd(0.05, Eigen::Vector3d::UnitX()).toRotationMatrix();
  s->contact.stamp = s->stamps[0];
  s->contact.radius = 0.01;
  return *s;
}

// Baseline mapping: every vertex tested against the ball, same per-vertex work as StampMapper (one contact).
void bruteForceMap(const Eigen::Matrix3Xd& rest, const enrichment::ContactStamp& c, double band, enrichment::SurfaceEnrichment& out) {
  out.vertices.clear();
  std::vector<Eigen::Vector3d> d;
  const Eigen::Matrix3d RB = c.rotation * c.frame;
  for (Eigen::Index v = 0; v < rest.cols(); ++v) {
    const Eigen::Vector3d x = rest.col(v) - c.contact;
    const double r = x.norm() / c.radius;
    if (r > 1.0) continue;
    const double s = std::clamp((1.0 - r) / band, 0.0, 1.0);
    const double a = s * s * (3.0 - 2.0 * s);
    if (a == 0.0) continue;
    out.vertices.push_back(static_cast<int>(v));
    d.push_back(a * (RB * enrichment::sampleStamp(c.stamp, c.radius, c.frame.col(0).dot(x), c.frame.col(1).dot(x))));
  }
  out.displacements.resize(3, static_cast<Eigen::Index>(d.size()));
  for (std::size_t k = 0; k < d.size(); ++k) out.displacements.col(static_cast<Eigen::Index>(k)) = d[k];
}

void BM_MappingKdTree(benchmark::State& state) {
  Scene& s = scene(static_cast<int>(state.range(0)));
  enrichment::SurfaceEnrichment e;
  for (auto _ : state) {
    s.mapper->map({s.contact}, e);
    benchmark::DoNotOptimize(e.displacements.data());
  }
  state.counters["touched"] = static_cast<double>(e.vertices.size());
}

void BM_MappingBruteForce(benchmark::State& state) {
  Scene& s = scene(static_cast<int>(state.range(0)));
  enrichment::SurfaceEnrichment e;
  for (auto _ : state) {
    bruteForceMap(s.rest, s.contact, s.mapper->rimBand(), e);
    benchmark::DoNotOptimize(e.displacements.data());
  }
  state.counters["touched"] = static_cast<double>(e.vertices.size());
}

void BM_FrameEnrich(benchmark::State& state) {
  Scene& s = scene(static_cast<int>(state.range(0)));
  enrichment::Correlation correlation;
  enrichment::RbfWeights weights;
  enrichment::SurfaceEnrichment e;
  Eigen::Matrix3Xd enriched;
  enrichment::ContactStamp contact = s.contact;
  for (auto _ : state) {
    enrichment::correlate(*s.table, s.rho[3], s.mu[3], kWidths, correlation);  // eq. (15)
    s.rbf->interpolate(correlation.weights, weights);
    contact.stamp = enrichment::blendStamps(s.stamps, weights.weights);  // eq. (16)
    s.mapper->map({contact}, e);
    enriched = s.rest;  // the coarse state stands in for s
    s.mapper->apply(e, enriched);  // eq. (1)
    benchmark::DoNotOptimize(enriched.data());
  }
  state.counters["touched"] = static_cast<double>(e.vertices.size());
}

void BM_FrameCopy(benchmark::State& state) {
  Scene& s = scene(static_cast<int>(state.range(0)));
  Eigen::Matrix3Xd enriched;
  for (auto _ : state) {
    enriched = s.rest;
    benchmark::DoNotOptimize(enriched.data());
  }
}

}  // namespace

BENCHMARK(BM_MappingKdTree)->Name("Mapping/KdTree")->Arg(50000)->ArgName("vertices")->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_MappingBruteForce)->Name("Mapping/BruteForce")->Arg(50000)->ArgName("vertices")->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_FrameEnrich)->Name("Frame/Enrich")->Arg(50000)->ArgName("vertices")->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_FrameCopy)->Name("Frame/Copy")->Arg(50000)->ArgName("vertices")->Unit(benchmark::kMicrosecond);

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  de_bench::RatioReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  reporter.printRatios("KdTree", "BruteForce");
  reporter.printRatios("Enrich", "Copy");
  benchmark::Shutdown();
  return 0;
}
