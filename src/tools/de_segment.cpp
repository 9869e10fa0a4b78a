// de_segment: site segmentation of [Seiler14 §6.1]. Site descriptors (orders 0..N, in each vertex's
// stamping frame) at every surface vertex, clustered by k-means under d_rho; prints the labels as JSON.
//
//   de_segment --mesh M.node|M.obj|M.ply --scale h --clusters k [--order N] [--quadrature volume|average]
//              [--cutoff c] [--sample-spacing s] [--output labels.json]
#include <CLI/CLI.hpp>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>

#include "deformation_enrichment/descriptors/evaluator_loading.hpp"
#include "descriptor_cli.hpp"
#include "deformation_enrichment/descriptors/site_segmentation.hpp"
#include "deformation_enrichment/atomic_file.hpp"
#include "deformation_enrichment/error.hpp"
#include "command_line.hpp"

using namespace deformation_enrichment;
using Json = nlohmann::ordered_json;

int main(int argc, char** argv) {
  CLI::App app{"Site segmentation ([Seiler14 §6.1]): k-means on d_rho over all surface vertices"};
  tools::DescriptorCli cli;
  std::string outputPath;
  int clusters = 6, restarts = 4;
  cli.addTo(app);
  app.add_option("--clusters", clusters, "number of clusters k")->capture_default_str();
  app.add_option("--restarts", restarts, "deterministic k-means++ restarts")->capture_default_str();
  app.add_option("--output", outputPath, "write the JSON here instead of stdout");
  if (const auto exitCode = deformation_enrichment::tools::parseCommandLine(app, argc, argv)) return *exitCode;

  try {
    const descriptors::LoadedObject object = cli.load();
    descriptors::KMeansOptions kmeans;
    kmeans.clusters = clusters;
    kmeans.restarts = restarts;
    const descriptors::SiteSegmentation segmentation = descriptors::segmentSites(object.evaluator, kmeans);

    Json output;
    output["mesh"] = cli.meshPath;
    output["sampling"] = object.sampling;
    output["scale"] = cli.scale;
    output["order"] = cli.order;
    output["clusters"] = clusters;
    output["inertia"] = segmentation.clusters.inertia;
    std::vector<int> sizes(clusters, 0);
    for (int label : segmentation.clusters.labels) ++sizes[label];
    output["cluster_sizes"] = sizes;
    // Surface vertex i has label labels[i]; for tet meshes surface_to_volume[i] is its .node index.
    output["labels"] = segmentation.clusters.labels;
    if (!segmentation.surfaceToSample.empty()) output["surface_to_volume"] = segmentation.surfaceToSample;
    Json vertices = Json::array();
    const auto& surface = object.evaluator.surface();
    for (Eigen::Index v = 0; v < surface.numVertices(); ++v)
      vertices.push_back({surface.vertices(0, v), surface.vertices(1, v), surface.vertices(2, v)});
    output["surface_vertices"] = vertices;
    if (outputPath.empty()) {
      std::cout << output.dump() << '\n';
    } else {
      writeFileAtomically(outputPath, output.dump() + '\n');
    }
    return 0;
  } catch (const std::exception& error) {
    std::cerr << "de_segment: " << error.what() << '\n';
    return 2;
  }
}
