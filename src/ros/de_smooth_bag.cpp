// de_smooth_bag: smooths a recorded mesh-state topic of a bag in shape space ([Brandt16]) and writes a new
// bag with every other message copied unchanged and the topic replaced by its smoothed states (same stamps).
//   de_smooth_bag --input in.bag --output out.bag --topic /mesh_state (--topology rest.obj | --topology-topic /rest_mesh)
//                 [--iterations K] [--tau T] [--restoring R] [--closed] [--subspace d]
#include <rosbag/bag.h>
#include <rosbag/view.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/mesh_io.hpp"
#include "deformation_enrichment/ros/conversions.hpp"
#include "deformation_enrichment/seconds_since.hpp"
#include "deformation_enrichment/shape_space/blas_threads.hpp"
#include "deformation_enrichment/shape_space/discrete_shells.hpp"
#include "deformation_enrichment/shape_space/smoothing_flow.hpp"
#include "../tools/command_line.hpp"

namespace de = deformation_enrichment;
namespace ss = de::shape_space;

namespace {

struct Run {
  int accepted = 0, unconverged = 0;
  std::string energies;  ///< eq. 4 (fine mesh) before and after every accepted step, comma-separated
};

// Up to `iterations` flow steps; a stalled step ends the run (later steps would stall the same way).
Run smooth(ss::SmoothingFlow& flow, int iterations) {
  const auto number = [](double v) {
    char text[32];
    std::snprintf(text, sizeof(text), "%.9g", v);
    return std::string(text);
  };
  Run run;
  run.energies = number(flow.pathEnergy());
  for (int k = 0; k < iterations; ++k) {
    const ss::FlowStep step = flow.step();
    if (step.stalled) {
      std::fprintf(stderr, "de_smooth_bag: step %d/%d stalled (no tau lowers the path energy), the run ends here\n", k + 1, iterations);
      break;
    }
    ++run.accepted;
    run.unconverged += step.unconvergedAverages;
    run.energies += ", " + number(flow.pathEnergy());
    std::fprintf(stderr, "de_smooth_bag: step %d/%d %spath energy %.6g (tau %.3g)%s\n", k + 1, iterations,
                 flow.ghostVertices() > 0 ? "ghost-mesh " : "", step.pathEnergy, step.tau,
                 step.unconvergedAverages > 0 ? ", some averages not converged" : "");
  }
  return run;
}

// The input bag with the topic's states replaced by `shapes` (same stamps and layout), the rest copied.
void writeSmoothed(rosbag::Bag& in, const std::string& output, const std::string& topic,
                   const std::vector<sensor_msgs::PointCloud2ConstPtr>& clouds, const std::vector<Eigen::VectorXd>& shapes) {
  rosbag::Bag out(output, rosbag::bagmode::Write);
  size_t next = 0;
  for (const rosbag::MessageInstance& m : rosbag::View(in)) {
    if (m.getTopic() == topic || m.getTopic() == "/" + topic) {
      sensor_msgs::PointCloud2 smoothed = *clouds[next];
      de::ros_layer::writePositions(ss::unflatten(shapes[next]).cast<float>(), smoothed);
      out.write(m.getTopic(), m.getTime(), smoothed);
      ++next;
    } else {
      out.write(m.getTopic(), m.getTime(), m, m.getConnectionHeader());
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Smooth a mesh-state topic of a bag in shape space and write a new bag"};
  std::string input, output, topic, topologyFile, topologyTopic;
  int iterations = 10, subspace = 0;
  double tau = 0.5, restoring = 0.0;
  bool closed = false;
  app.add_option("--input", input, "input bag")->required();
  app.add_option("--output", output, "output bag")->required();
  app.add_option("--topic", topic, "sensor_msgs/PointCloud2 mesh-state topic")->required();
  app.add_option("--topology", topologyFile, "OBJ/PLY file with the shared triangles");
  app.add_option("--topology-topic", topologyTopic, "pcl_msgs/PolygonMesh topic in the bag with the triangles");
  app.add_option("--iterations", iterations, "flow steps")->check(CLI::NonNegativeNumber);
  app.add_option("--tau", tau, "step size in (0, 1]");
  app.add_option("--restoring", restoring, "restoring force rho in [0, 1)");
  app.add_flag("--closed", closed, "periodic sequence");
  app.add_option("--subspace", subspace, "reduced mode with this many PCA directions (0: full space)");
  if (const auto exitCode = deformation_enrichment::tools::parseCommandLine(app, argc, argv)) return *exitCode;
  ss::preferSingleThreadedBlas();
  if (topologyFile.empty() == topologyTopic.empty()) {
    std::fprintf(stderr, "de_smooth_bag: give exactly one of --topology and --topology-topic\n");
    return 2;
  }
  try {
    const auto start = std::chrono::steady_clock::now();
    rosbag::Bag in(input, rosbag::bagmode::Read);
    ss::ShapeSequence sequence;
    std::vector<sensor_msgs::PointCloud2ConstPtr> clouds;
    for (const rosbag::MessageInstance& m : rosbag::View(in, rosbag::TopicQuery(topic))) {
      const auto cloud = m.instantiate<sensor_msgs::PointCloud2>();
      if (!cloud) throw de::InvalidInputError("topic " + topic + " does not hold sensor_msgs/PointCloud2");
      clouds.push_back(cloud);
      sequence.shapes.push_back(ss::flatten(de::ros_layer::positionsFromCloud(*cloud).cast<double>()));
    }
    if (!topologyFile.empty()) {
      sequence.triangles = de::mesh::readTriangleMesh(topologyFile).triangles;
    } else {
      for (const rosbag::MessageInstance& m : rosbag::View(in, rosbag::TopicQuery(topologyTopic))) {
        if (const auto mesh = m.instantiate<pcl_msgs::PolygonMesh>()) sequence.triangles = de::ros_layer::triangleMeshFromMessage(*mesh).triangles;
      }
      if (sequence.triangles.cols() == 0) throw de::InvalidInputError("no PolygonMesh on " + topologyTopic);
    }
    std::fprintf(stderr, "de_smooth_bag: %zu states of %ld vertices from %s\n", clouds.size(),
                 static_cast<long>(sequence.numVertices()), topic.c_str());
    ss::validateSequence(sequence, 3);
    // GOAST's shell energy, bending scaled to the mesh size (as de_smooth)
    const ss::DiscreteShells energy(sequence.triangles, sequence.numVertices(),
                                    ss::DiscreteShellsOptions::hyperelasticFor(sequence.shapes.front()));
    ss::FlowOptions options;
    options.tau = tau;
    options.rho = restoring;
    options.closed = closed;
    options.reduction.reduced = subspace > 0;
    if (options.reduction.reduced) options.reduction.subspaceDimension = subspace;
    options.parallelShapes = true;  // DiscreteShells is thread-safe; the Jacobi update makes shapes independent
    ss::SmoothingFlow flow(energy, std::move(sequence), options);
    std::fprintf(stderr, "de_smooth_bag: path energy %.6g\n", flow.pathEnergy());
    const Run run = smooth(flow, iterations);
    const int accepted = run.accepted;
    if (accepted == 0 && iterations > 0) {
      std::fprintf(stderr, "de_smooth_bag: no step was accepted; no bag written\n");
      return 3;
    }
    writeSmoothed(in, output, topic, clouds, flow.current().shapes);
    std::printf("{\"states\": %zu, \"accepted_steps\": %d, \"unconverged_averages\": %d, \"path_energy\": [%s], "
                "\"seconds\": %.3f}\n", clouds.size(), accepted, run.unconverged, run.energies.c_str(),
                de::secondsSince(start));
    return 0;
  } catch (const de::Error& e) {
    std::fprintf(stderr, "de_smooth_bag: %s\n", e.what());
    return 1;
  } catch (const rosbag::BagException& e) {
    std::fprintf(stderr, "de_smooth_bag: bag error: %s\n", e.what());
    return 1;
  }
}
