// Per-frame enrichment as the node runs it (target: <= 1 ms compute for a 50k-vertex surface with 10
// examples): ContactEnricher::enrich for one contact, i.e. the deformation descriptor (MLS F, polar, moments
// up to order 2 of the current state in the window), the cached site descriptor, eq. 15 weights, RBF, eq. 16
// blend of 32x32 stamps, mapping within R = 3 cm, plus s + e applied to a copy of the state
// (ContactEnricher/Enrich: the tool stays on one rest point, as while it holds the tissue, so the rest-point
// caches hit; ContactEnricher/EnrichMoving: the contact moves to another of 8 rest points every frame, so
// they miss; ContactEnricher/EnrichMovingFiltered: the same with the temporal filter), against only copying
// the state (ContactEnricher/Copy). The default slab settings: h = 6 mm,
// magnitude-aware stamps, rim band 0.1.
#include <benchmark/benchmark.h>

#include <memory>

#include "deformation_enrichment/enrichment/contact_enricher.hpp"
#include "deformation_enrichment/enrichment/temporal_filter.hpp"
#include "ratio_reporter.hpp"
#include "slab_bench_scene.hpp"

using namespace deformation_enrichment;

namespace {

struct Scene {
  std::unique_ptr<enrichment::ContactEnricher> enricher;
  Eigen::Matrix3Xd current;
  enrichment::Contact contact;
};

Scene& scene() {
  static std::unique_ptr<Scene> s;
  if (s) return *s;
  const de_bench::SlabBenchScene& slab = de_bench::slabBenchScene();
  s = std::make_unique<Scene>();
  s->enricher = std::make_unique<enrichment::ContactEnricher>(slab.surface, slab.options);
  s->enricher->setExamples(slab.set);
  s->contact.point = slab.contact;
  s->current = slab.current;
  return *s;
}

void BM_FrameEnrich(benchmark::State& state) {
  Scene& s = scene();
  enrichment::EnrichmentResult result;
  Eigen::Matrix3Xd enriched;
  for (auto _ : state) {
    s.enricher->enrich(s.current, {s.contact}, result);
    enriched = s.current;
    s.enricher->apply(result, enriched);  // eq. (1)
    benchmark::DoNotOptimize(enriched.data());
  }
  state.counters["vertices"] = static_cast<double>(s.current.cols());
  state.counters["touched"] = static_cast<double>(result.enrichment.vertices.size());
  state.counters["confidence"] = result.contacts.at(0).confidence;
  state.counters["descriptor_us"] = 1e6 * result.timings.descriptorSeconds;
  state.counters["blend_us"] = 1e6 * result.timings.blendSeconds;
  state.counters["map_us"] = 1e6 * result.timings.mapSeconds;
}

void BM_FrameEnrichMoving(benchmark::State& state) {
  Scene& s = scene();
  enrichment::EnrichmentResult result;
  Eigen::Matrix3Xd enriched;
  int frame = 0;
  for (auto _ : state) {
    enrichment::Contact contact = s.contact;
    contact.point.x() += 0.001 * (frame++ % 8);  // more rest points than the caches hold
    s.enricher->enrich(s.current, {contact}, result);
    enriched = s.current;
    s.enricher->apply(result, enriched);
    benchmark::DoNotOptimize(enriched.data());
  }
  state.counters["descriptor_us"] = 1e6 * result.timings.descriptorSeconds;
  state.counters["map_us"] = 1e6 * result.timings.mapSeconds;
}

// The moving contact with the temporal filter on (tau = 10 ms at 60 Hz): its latency cost per state.
void BM_FrameEnrichMovingFiltered(benchmark::State& state) {
  Scene& s = scene();
  enrichment::EnrichmentResult result;
  enrichment::TemporalFilter filter(0.01);
  Eigen::Matrix3Xd enriched;
  int frame = 0;
  for (auto _ : state) {
    enrichment::Contact contact = s.contact;
    contact.point.x() += 0.001 * (frame++ % 8);
    s.enricher->enrich(s.current, {contact}, result);
    filter.filter(result.enrichment, 1.0 / 60.0, s.current.cols());
    enriched = s.current;
    s.enricher->apply(result, enriched);
    benchmark::DoNotOptimize(enriched.data());
  }
  state.counters["touched"] = static_cast<double>(result.enrichment.vertices.size());
}

void BM_FrameCopy(benchmark::State& state) {
  Scene& s = scene();
  Eigen::Matrix3Xd enriched;
  for (auto _ : state) {
    enriched = s.current;
    benchmark::DoNotOptimize(enriched.data());
  }
}

}  // namespace

BENCHMARK(BM_FrameEnrich)->Name("ContactEnricher/Enrich/50k_vertices")->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_FrameEnrichMoving)->Name("ContactEnricher/EnrichMoving/50k_vertices")->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_FrameEnrichMovingFiltered)->Name("ContactEnricher/EnrichMovingFiltered/50k_vertices")->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_FrameCopy)->Name("ContactEnricher/Copy/50k_vertices")->Unit(benchmark::kMicrosecond);

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  de_bench::RatioReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  reporter.printRatios("Enrich", "Copy");
  reporter.printRatios("EnrichMoving", "Copy");
  reporter.printRatios("EnrichMovingFiltered", "EnrichMoving");
  benchmark::Shutdown();
  return 0;
}
