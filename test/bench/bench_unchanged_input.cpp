// "Unchanged input -> no recompute" in the enrichment node: is comparing a mesh state with the last one
// measurably cheaper than enriching it? 100k-vertex closed slab surface, float32 x y z buffer (1.2 MB, the
// PointCloud2 data of a state), 10 examples, one contact.
//   Check/Memcmp: memcmp of the state's buffer against the last one (what the node does).
//   Check/Hash:   std::hash of the buffer (the alternative: hash once per state, compare 8 bytes).
//   Check/Enrich: ContactEnricher::enrich for the contact (descriptors, eq. 15, RBF, eq. 16, mapping),
//                 what a detected unchanged state saves.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstring>
#include <memory>
#include <random>
#include <string_view>
#include <vector>

#include "deformation_enrichment/enrichment/contact_enricher.hpp"
#include "deformation_enrichment/mesh/grid_tet_mesh.hpp"
#include "deformation_enrichment/mesh/tet_surface.hpp"
#include "ratio_reporter.hpp"

using namespace deformation_enrichment;

namespace {

struct Scene {
  std::unique_ptr<enrichment::ContactEnricher> enricher;
  Eigen::Matrix3Xd current;
  std::vector<uint8_t> buffer, last;  // this and the previous state's float32 x y z
  enrichment::Contact contact;
};

Scene& scene() {
  static std::unique_ptr<Scene> s;
  if (s) return *s;
  s = std::make_unique<Scene>();
  const mesh::TriangleMesh rest = mesh::extractSurface(mesh::gridTetMesh(Eigen::Vector3d(-0.05, -0.05, 0.0),
                                                                         Eigen::Vector3d(0.05, 0.05, 0.02),
                                                                         Eigen::Vector3i(223, 223, 1)))
                                      .surface;
  s->current = rest.vertices;
  for (Eigen::Index v = 0; v < rest.vertices.cols(); ++v) {  // a sheared dent at the top centre
    const double g = std::exp(-rest.vertices.col(v).head<2>().squaredNorm() / (2.0 * 0.008 * 0.008));
    s->current.col(v) += g * rest.vertices(2, v) / 0.02 * Eigen::Vector3d(0.001, 0.0005, -0.002);
  }
  enrichment::ContactEnricherOptions options;
  options.descriptors.window.scale = 0.006;
  options.stampRadius = 0.02;
  options.sampleSpacing = 0.002;
  s->enricher = std::make_unique<enrichment::ContactEnricher>(rest, options);
  examples::ExampleSet set;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> offset(-0.01, 0.01);
  for (int i = 0; i < 10; ++i) {
    enrichment::Contact c;
    c.point = Eigen::Vector3d(offset(rng), offset(rng), 0.02);
    const enrichment::ContactDescription d = s->enricher->describe(s->current, c);
    examples::Example e;
    e.contact = d.p;
    e.frame = d.B;
    e.rho = d.rho;
    e.mu = d.mu;
    e.stamp = cv::Mat(64, 64, CV_32FC3);
    cv::randn(e.stamp, cv::Scalar::all(0.0), cv::Scalar::all(1e-4));
    e.stampRadius = 0.02;
    set.examples.push_back(e);
  }
  s->enricher->setExamples(set);
  s->contact.point = Eigen::Vector3d(0.0, 0.0, 0.02);
  const Eigen::Matrix3Xf positions = s->current.cast<float>();
  s->buffer.resize(sizeof(float) * 3 * static_cast<std::size_t>(positions.cols()));
  std::memcpy(s->buffer.data(), positions.data(), s->buffer.size());
  s->last = s->buffer;
  return *s;
}

void BM_Memcmp(benchmark::State& state) {
  Scene& s = scene();
  for (auto _ : state) {
    const bool same = std::memcmp(s.buffer.data(), s.last.data(), s.buffer.size()) == 0;
    benchmark::DoNotOptimize(same);
  }
  state.counters["bytes"] = static_cast<double>(s.buffer.size());
}

void BM_Hash(benchmark::State& state) {
  Scene& s = scene();
  for (auto _ : state) {
    const std::size_t h =
        std::hash<std::string_view>()(std::string_view(reinterpret_cast<const char*>(s.buffer.data()), s.buffer.size()));
    benchmark::DoNotOptimize(h);
  }
  state.counters["bytes"] = static_cast<double>(s.buffer.size());
}

void BM_Enrich(benchmark::State& state) {
  Scene& s = scene();
  enrichment::EnrichmentResult result;
  for (auto _ : state) {
    s.enricher->enrich(s.current, {s.contact}, result);
    benchmark::DoNotOptimize(result.enrichment.displacements.data());
  }
  state.counters["touched"] = static_cast<double>(result.enrichment.vertices.size());
  state.counters["vertices"] = static_cast<double>(s.current.cols());
}

}  // namespace

BENCHMARK(BM_Memcmp)->Name("Check/Memcmp/points:100000")->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Hash)->Name("Check/Hash/points:100000")->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Enrich)->Name("Check/Enrich/points:100000")->Unit(benchmark::kMicrosecond);

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  de_bench::RatioReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  reporter.printRatios("Memcmp", "Hash");
  reporter.printRatios("Memcmp", "Enrich");
  benchmark::Shutdown();
  return 0;
}
