// The contact of a tool pose on a 100k-vertex surface (ContactTracker::updateFromToolPose, run by the node
// for each tool on every mesh state): a URDF sphere tip (4 mm) measured exactly against the triangles, next
// to the point tip's vertex test. No master needed.
#include <benchmark/benchmark.h>
#include <tf2_ros/buffer.h>

#include "deformation_enrichment/mesh/grid_tet_mesh.hpp"
#include "deformation_enrichment/mesh/tet_surface.hpp"
#include "deformation_enrichment/mesh/triangle_mesh.hpp"
#include "deformation_enrichment/ros/contact_tracker.hpp"
#include "ratio_reporter.hpp"

namespace de = deformation_enrichment;

namespace {

void contactOfPose(benchmark::State& state, bool sphere) {
  // About 100k surface vertices (10 x 10 x 2 cm, 0.35 mm on top).
  const de::mesh::TriangleMesh surface = de::mesh::extractSurface(de::mesh::gridTetMesh(
      Eigen::Vector3d(-0.05, -0.05, 0.0), Eigen::Vector3d(0.05, 0.05, 0.02), Eigen::Vector3i(220, 220, 4))).surface;
  const Eigen::Matrix3Xf positions = surface.vertices.cast<float>();
  const Eigen::Matrix3Xd normals = de::mesh::vertexNormals(surface);
  tf2_ros::Buffer tf;
  de::ros_layer::ContactTracker tracker(tf, ros::Duration(0.5));
  geometry_msgs::PoseStamped pose;
  pose.header.frame_id = "mesh";
  pose.pose.orientation.w = 1.0;
  const de::ros_layer::ToolTip tip = sphere ? de::ros_layer::ToolTip("tip", {{de::ros_layer::TipPrimitive::Shape::Sphere,
                                                                             Eigen::Isometry3d::Identity(),
                                                                             Eigen::Vector3d(0.004, 0, 0)}})
                                              : de::ros_layer::ToolTip();
  int k = 0;
  for (auto _ : state) {
    pose.pose.position.x = 0.0001 * (k++ % 100);  // sliding over the top, 1 mm above it
    pose.pose.position.z = 0.021 + (sphere ? 0.004 : 0.0);
    tracker.updateFromToolPose(pose, "tool", "mesh", positions, normals, 0.003, tip, sphere ? &surface.triangles : nullptr);
    benchmark::DoNotOptimize(tracker);
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
