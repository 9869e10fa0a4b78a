// The contact of a tool pose on a 100k-vertex surface (enrichment::toolProximity, run by the node for each
// tool on every mesh state): a URDF sphere tip (4 mm) measured exactly against the triangles, next to the
// point tip's vertex test.
#include <benchmark/benchmark.h>

#include "deformation_enrichment/mesh/grid_tet_mesh.hpp"
#include "deformation_enrichment/mesh/tet_surface.hpp"
#include "deformation_enrichment/mesh/triangle_mesh.hpp"
#include "deformation_enrichment/enrichment/tool_proximity.hpp"
#include "ratio_reporter.hpp"

namespace de = deformation_enrichment;

namespace {

void contactOfPose(benchmark::State& state, bool sphere) {
  // About 100k surface vertices (10 x 10 x 2 cm, 0.35 mm on top).
  const de::mesh::TriangleMesh surface = de::mesh::extractSurface(de::mesh::gridTetMesh(
      Eigen::Vector3d(-0.05, -0.05, 0.0), Eigen::Vector3d(0.05, 0.05, 0.02), Eigen::Vector3i(220, 220, 4))).surface;
  const Eigen::Matrix3Xf positions = surface.vertices.cast<float>();
  const de::enrichment::ToolTip tip =
      sphere ? de::enrichment::ToolTip("tip", {{de::enrichment::TipPrimitive::Shape::Sphere, Eigen::Isometry3d::Identity(),
                                                Eigen::Vector3d(0.004, 0, 0)}})
             : de::enrichment::ToolTip();
  Eigen::ArrayXf scratch;
  int k = 0;
  for (auto _ : state) {
    // Sliding over the top, 1 mm above it.
    const Eigen::Isometry3d pose(Eigen::Translation3d(0.0001 * (k++ % 100), 0.0, 0.021 + (sphere ? 0.004 : 0.0)));
    const de::enrichment::ToolProximity contact =
        de::enrichment::toolProximity(pose, tip, positions, 0.003, sphere ? &surface.triangles : nullptr, scratch);
    benchmark::DoNotOptimize(contact);
  }
  state.counters["vertices"] = static_cast<double>(surface.vertices.cols());
}

}  // namespace

BENCHMARK_CAPTURE(contactOfPose, sphere, true)->Name("ToolContact/SphereTip/points:100k")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(contactOfPose, point, false)->Name("ToolContact/PointTip/points:100k")->Unit(benchmark::kMicrosecond);

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  de_bench::RatioReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  reporter.printRatios("SphereTip", "PointTip");
  benchmark::Shutdown();
  return 0;
}
