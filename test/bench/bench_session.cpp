// What the enrichment node's frame path costs through the EnrichmentSession, on the ~50k-vertex slab with 10
// examples (slab_bench_scene.hpp):
//   Session/EnrichMoving/50k: one state with the tool sliding 0.5 mm per state, back and forth over 4 mm (every
//     state touches a new rest point, so the rest-point caches miss; one site, as a sliding tool makes): float
//     state in, continuity, the enricher, enriched float state out; next to
//     Session/Copy/50k, copying the float state (what publishing an unchanged state costs at least).
//   Session/Examples128/50k vs Session/Examples10/50k: the sliding state with 128 and with 10 examples of the
//     slab scene's volume stamps (stamp.layers layers of 32 x 32) blended by the default regression.
//   Session/OpenVolume/50k: the same on the slab's top face alone (open) with the slab's tets as its volume.
//   Rebuild/Offthread/50k vs Rebuild/Onthread/50k: a new rest surface (a cut: another topology of ~50k
//     vertices) arrives while states come at 60 Hz. The reported time of an iteration is the longest delay of
//     an output behind its input's due time over the episode (manual time): with the session the enricher is
//     built on its worker and states keep flowing; the baseline builds it on the frame thread, so the states behind
//     it wait.
//   Scale/1M/... vs Scale/50k/...: a ~1M-vertex rest surface (700 x 700 x 1 cells) against the 50k one: the
//     time from setRestGeometry to a built enricher (Build, one iteration, manual time) with the process's
//     resident memory after it (counter rss_mb, /proc/self/status), and a sliding state (EnrichMoving).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <fstream>
#include <string>
#include <thread>

#include "deformation_enrichment/enrichment/enrichment_session.hpp"
#include "ratio_reporter.hpp"
#include "../unit/top_face.hpp"
#include "slab_bench_scene.hpp"

namespace de = deformation_enrichment;

namespace {

using Clock = std::chrono::steady_clock;
constexpr double kPeriod = 1.0 / 60.0;

std::unique_ptr<de::enrichment::EnrichmentSession> session(const de::mesh::TriangleMesh& rest) {
  auto s = std::make_unique<de::enrichment::EnrichmentSession>(de::enrichment::SessionOptions());
  s->setExampleSet(de_bench::slabBenchScene().set);
  s->setRestGeometry({rest, std::nullopt, "bench"});
  s->waitForRebuild();
  return s;
}

// The tool's contact sliding 0.5 mm per state, back and forth over 4 mm from `start`.
Eigen::Vector3d slidingPoint(const Eigen::Vector3d& start, int frame) {
  const int step = frame % 16;
  return start + Eigen::Vector3d(0.0005 * (step < 8 ? step : 16 - step), 0.0, 0.0);
}

double residentMegabytes() {
  std::ifstream status("/proc/self/status");
  for (std::string line; std::getline(status, line);)
    if (line.rfind("VmRSS:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;  // kB
  return 0.0;
}

void enrichSliding(benchmark::State& state, de::enrichment::EnrichmentSession& s, const Eigen::Matrix3Xf& current,
                   const Eigen::Vector3d& contact) {
  int frame = 0;
  std::size_t touched = 0, released = 0;
  for (auto _ : state) {
    const de::enrichment::FrameResult& result = s.enrich(current, {{"tool", slidingPoint(contact, frame)}}, 0.01 * frame);
    ++frame;
    touched = result.verticesTouched;
    released = result.releasedSites;
    benchmark::DoNotOptimize(s.enrichedPositions().data());
  }
  state.counters["vertices"] = static_cast<double>(current.cols());
  state.counters["touched"] = static_cast<double>(touched);
  state.counters["released_sites"] = static_cast<double>(released);
}

void BM_SessionEnrichMoving(benchmark::State& state) {
  const de_bench::SlabBenchScene& scene = de_bench::slabBenchScene();
  auto s = session(scene.surface);
  const Eigen::Matrix3Xf current = scene.current.cast<float>();
  enrichSliding(state, *s, current, scene.contact);
}

// `count` examples with the slab scene's volume stamps.
void BM_SessionExamples(benchmark::State& state, int count) {
  const de_bench::SlabBenchScene& scene = de_bench::slabBenchScene();
  const de::scene_file::SceneDescription slab = de::scene_file::readSceneFile(de::scene_file::findSceneFile("slab"));
  de::enrichment::EnrichmentSession s{de::enrichment::SessionOptions()};
  s.setExampleSet(de_bench::slabBenchSet(scene.surface, scene.options, slab, count, slab.stamp.layers));
  s.setRestGeometry({scene.surface, std::nullopt, "bench"});
  s.waitForRebuild();
  const Eigen::Matrix3Xf current = scene.current.cast<float>();
  enrichSliding(state, s, current, scene.contact);
  state.counters["examples"] = count;
}

// The slab's top face alone (an open surface, every vertex kept) given the slab's tet mesh as its volume: the
// site descriptor's density comes from the volume, the frame path is the same.
void BM_SessionEnrichMovingOpen(benchmark::State& state) {
  const de_bench::SlabBenchScene& scene = de_bench::slabBenchScene();
  const de::mesh::TetMesh volume = de_bench::slabVolume(150);
  auto s = std::make_unique<de::enrichment::EnrichmentSession>(de::enrichment::SessionOptions());
  s->setExampleSet(scene.set);
  s->setRestGeometry({de_test::topFace(scene.surface, 0.02), volume, "bench open"});
  s->waitForRebuild();
  if (s->diagnostics().siteDensity.find("volume") == std::string::npos) state.SkipWithError("the open surface is not described from its volume");
  const Eigen::Matrix3Xf current = scene.current.cast<float>();
  enrichSliding(state, *s, current, scene.contact);
}

// `cells` x `cells` x 1 slab cells: 700 gives ~1M surface vertices.
void BM_ScaleBuild(benchmark::State& state, int cells) {
  const de::mesh::TriangleMesh surface = de_bench::slabSurface(cells, 1);
  for (auto _ : state) {
    de::enrichment::EnrichmentSession s{de::enrichment::SessionOptions()};
    s.setExampleSet(de_bench::slabBenchScene().set);
    const Clock::time_point start = Clock::now();
    s.setRestGeometry({surface, std::nullopt, "scale"});
    s.waitForRebuild();
    state.SetIterationTime(std::chrono::duration<double>(Clock::now() - start).count());
    state.counters["rss_mb"] = residentMegabytes();
  }
  state.counters["vertices"] = static_cast<double>(surface.numVertices());
}

void BM_ScaleEnrichMoving(benchmark::State& state, int cells) {
  const de::mesh::TriangleMesh surface = de_bench::slabSurface(cells, 1);
  auto s = session(surface);
  const Eigen::Vector3d contact(0.003, -0.002, 0.02);
  const Eigen::Matrix3Xf current = de_bench::dented(surface.vertices, contact, 0.0025, Eigen::Vector3d(0.0004, 0, 0)).cast<float>();
  enrichSliding(state, *s, current, contact);
}

void BM_SessionCopy(benchmark::State& state) {
  const Eigen::Matrix3Xf current = de_bench::slabBenchScene().current.cast<float>();
  Eigen::Matrix3Xf copy;
  for (auto _ : state) {
    copy = current;
    benchmark::DoNotOptimize(copy.data());
  }
}

// One episode: states at 60 Hz on `before`; after 5 states the cut surface arrives (handed to `cut`, on the
// frame thread, as a rest-mesh callback runs in the node); states of the new topology follow; the episode
// ends 5 states after the new surface is enriched. Returns the longest delay of an output behind its due time.
template <typename Cut, typename Enrich, typename Ready>
double rebuildEpisode(const Eigen::Matrix3Xf& before, const Eigen::Matrix3Xf& after, Cut cut, Enrich enrich, Ready ready) {
  const Clock::time_point start = Clock::now();
  double longest = 0.0;
  int afterReady = -1;
  for (int k = 0; afterReady < 5 && k < 600; ++k) {
    const Clock::time_point due = start + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(k * kPeriod));
    std::this_thread::sleep_until(due);
    if (k == 5) cut();
    enrich(k < 5 ? before : after, k * kPeriod);
    longest = std::max(longest, std::chrono::duration<double>(Clock::now() - due).count());
    if (afterReady >= 0 || (k >= 5 && ready())) ++afterReady;
  }
  return longest;
}

void BM_RebuildOffthread(benchmark::State& state) {
  const de_bench::SlabBenchScene& scene = de_bench::slabBenchScene();
  const de::mesh::TriangleMesh cutSurface = de_bench::slabSurface(149);  // another topology, ~49k vertices
  const Eigen::Matrix3Xf before = scene.current.cast<float>(), after = cutSurface.vertices.cast<float>();
  for (auto _ : state) {
    auto s = session(scene.surface);
    const double longest = rebuildEpisode(
        before, after, [&] { s->setRestGeometry({cutSurface, std::nullopt, "cut"}); },
        [&](const Eigen::Matrix3Xf& positions, double t) { s->enrich(positions, {{"tool", scene.contact}}, t); },
        [&] { return !s->diagnostics().rebuilding; });
    state.SetIterationTime(longest);
  }
}

void BM_RebuildOnthread(benchmark::State& state) {
  const de_bench::SlabBenchScene& scene = de_bench::slabBenchScene();
  const de::mesh::TriangleMesh cutSurface = de_bench::slabSurface(149);
  const Eigen::Matrix3Xf before = scene.current.cast<float>(), after = cutSurface.vertices.cast<float>();
  for (auto _ : state) {
    auto enricher = std::make_unique<de::enrichment::ContactEnricher>(scene.surface, scene.options);
    enricher->setExamples(scene.set);
    de::enrichment::EnrichmentResult result;
    const double longest = rebuildEpisode(
        before, after,
        [&] {
          enricher = std::make_unique<de::enrichment::ContactEnricher>(cutSurface, scene.options);
          enricher->setExamples(scene.set);
        },
        [&](const Eigen::Matrix3Xf& positions, double) {
          de::enrichment::Contact contact;
          contact.point = scene.contact;
          contact.restState = false;
          enricher->enrich(positions, {contact}, result);
        },
        [] { return true; });
    state.SetIterationTime(longest);
  }
}

}  // namespace

BENCHMARK(BM_SessionEnrichMoving)->Name("Session/EnrichMoving/50k")->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_SessionEnrichMovingOpen)->Name("Session/OpenVolume/50k")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_SessionExamples, many, 128)->Name("Session/Examples128/50k")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_SessionExamples, few, 10)->Name("Session/Examples10/50k")->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_SessionCopy)->Name("Session/Copy/50k")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_ScaleBuild, large, 700)->Name("Scale/1M/Build")->Unit(benchmark::kMillisecond)->UseManualTime()->Iterations(1);
BENCHMARK_CAPTURE(BM_ScaleBuild, small, 150)->Name("Scale/50k/Build")->Unit(benchmark::kMillisecond)->UseManualTime()->Iterations(1);
BENCHMARK_CAPTURE(BM_ScaleEnrichMoving, large, 700)->Name("Scale/1M/EnrichMoving")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_ScaleEnrichMoving, small, 150)->Name("Scale/50k/EnrichMoving")->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_RebuildOffthread)->Name("Rebuild/Offthread/50k")->Unit(benchmark::kMillisecond)->UseManualTime()->Iterations(3);
BENCHMARK(BM_RebuildOnthread)->Name("Rebuild/Onthread/50k")->Unit(benchmark::kMillisecond)->UseManualTime()->Iterations(3);

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  de_bench::RatioReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  reporter.printRatios("EnrichMoving", "Copy");
  reporter.printRatios("OpenVolume", "EnrichMoving");
  reporter.printRatios("Examples128", "Examples10");
  reporter.printRatios("Offthread", "Onthread");
  reporter.printRatios("1M", "50k");
  std::printf("(Rebuild: the longest delay of an output behind its input at 60 Hz while a new 50k-vertex rest surface is "
              "built; goal: below one period, %.1f ms)\n", 1e3 * kPeriod);
  benchmark::Shutdown();
  return 0;
}
