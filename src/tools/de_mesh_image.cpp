// de_mesh_image: a display surface and a coarse tet mesh from a segmented image (docs/liver.md), like
// SOFA's liver-smooth.obj and liver.msh. Deterministic: the same image and options give the same bytes.
//
//   de_mesh_image --image liver.inr.gz --output DIR [--display-vertices 10000] [--coarse-vertices 400]
//                 [--sigma 0.0015] [--min-label 1] [--fine]
//
// Writes DIR/display.obj (metres), DIR/coarse.node/.ele (TetGen), with --fine DIR/fine.node/.ele (tetgen
// -pqY of the display surface: its first nodes are the display vertices), and DIR/mesh_image.json
// (sizes and how far display vertices lie outside the coarse volume); times go to stdout only.
#include <CLI/CLI.hpp>
#include <chrono>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>

#include "deformation_enrichment/atomic_file.hpp"
#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/barycentric_embedding.hpp"
#include "deformation_enrichment/mesh/image_surface.hpp"
#include "deformation_enrichment/mesh/label_image.hpp"
#include "deformation_enrichment/mesh/mesh_io.hpp"
#include "deformation_enrichment/mesh/surface_report.hpp"
#include "deformation_enrichment/mesh/tetgen_io.hpp"
#include "deformation_enrichment/mesh/tetrahedralisation.hpp"
#include "deformation_enrichment/seconds_since.hpp"
#include "command_line.hpp"

using namespace deformation_enrichment;
using Json = nlohmann::ordered_json;
using Clock = std::chrono::steady_clock;

namespace {
}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Display surface and coarse tet mesh from a segmented image (CGAL ImageIO, VTK, tetgen)"};
  std::string imagePath, output;
  mesh::ImageSurfaceOptions surfaceOptions;
  mesh::CoarseVolumeOptions coarseOptions;
  bool fine = false;
  app.add_option("--image", imagePath, "label image (.inr, .inr.gz, ...; voxel size in mm)")->required();
  app.add_option("--output", output, "folder to write into (created)")->required();
  app.add_option("--display-vertices", surfaceOptions.targetVertices, "vertex budget of the display surface")->capture_default_str();
  app.add_option("--coarse-vertices", coarseOptions.simplification.targetVertices, "vertices of the coarse boundary")->capture_default_str();
  app.add_option("--sigma", surfaceOptions.smoothingSigma, "Gaussian smoothing of the label field, metres")->capture_default_str();
  app.add_option("--min-label", surfaceOptions.minLabel, "labels >= this are the object")->capture_default_str();
  app.add_flag("--fine", fine, "also write the fine model tetgen -pqY makes of the display surface");
  if (const auto exitCode = deformation_enrichment::tools::parseCommandLine(app, argc, argv)) return *exitCode;

  try {
    std::filesystem::create_directories(output);
    auto start = Clock::now();
    const mesh::LabelImage image = mesh::readLabelImage(imagePath);
    const mesh::TriangleMesh display = mesh::imageSurface(image, surfaceOptions);
    mesh::writeTriangleMesh(output + "/display.obj", display);
    std::cout << "display surface: " << mesh::describe(mesh::inspectSurface(display)) << " (" << secondsSince(start) << " s)\n";

    start = Clock::now();
    const mesh::CoarseVolume coarse = mesh::coarseVolume(display, coarseOptions);
    mesh::writeTetGen(output + "/coarse", coarse.volume.mesh);
    const double diagonal = (display.vertices.rowwise().maxCoeff() - display.vertices.rowwise().minCoeff()).norm();
    const mesh::BarycentricEmbedding embedding = mesh::embedPoints(coarse.volume.mesh, display.vertices, diagonal);
    std::cout << "coarse volume: " << coarse.volume.mesh.numVertices() << " nodes, " << coarse.volume.mesh.numTets()
              << " tets, boundary moved out " << coarse.inflation << " m (" << secondsSince(start) << " s); "
              << mesh::describe(embedding.report, display.numVertices()) << "\n";

    Json report;
    report["image"] = {{"voxels", {image.size.x(), image.size.y(), image.size.z()}},
                       {"spacing_m", {image.spacing.x(), image.spacing.y(), image.spacing.z()}}};
    report["display"] = {{"file", "display.obj"}, {"vertices", display.numVertices()}, {"triangles", display.numTriangles()}};
    report["coarse"] = {{"files", "coarse.node, coarse.ele"}, {"nodes", coarse.volume.mesh.numVertices()},
                        {"tets", coarse.volume.mesh.numTets()}, {"tetgen", coarse.volume.command},
                        {"boundary_vertices", coarse.boundaryVertices}, {"inflation_m", coarse.inflation}};
    report["display_outside_coarse"] = {{"vertices", embedding.report.outside},
                                        {"max_m", embedding.report.maxDistance},
                                        {"mean_m", embedding.report.meanDistance}};
    if (fine) {
      start = Clock::now();
      const mesh::Tetrahedralisation model = mesh::tetrahedralise(display);
      mesh::writeTetGen(output + "/fine", model.mesh);
      std::cout << "fine model: " << model.mesh.numVertices() << " nodes, " << model.mesh.numTets() << " tets ("
                << secondsSince(start) << " s)\n";
      report["fine"] = {{"files", "fine.node, fine.ele"}, {"nodes", model.mesh.numVertices()},
                        {"tets", model.mesh.numTets()}, {"tetgen", model.command},
                        {"display_vertices_first", model.surfaceVertices}};
    }
    writeFileAtomically(output + "/mesh_image.json", report.dump(2) + '\n');
    return 0;
  } catch (const Error& error) {
    std::cerr << "de_mesh_image: " << error.what() << '\n';
    return 1;
  }
}
