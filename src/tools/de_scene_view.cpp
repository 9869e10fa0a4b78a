// de_scene_view: the rviz view of a scene for the demo (scripts/demo --scene): reads the scene's display
// surface (scenes::sceneGeometry), writes a copy of an rviz config whose orbit camera looks at it from the
// template's angles at a distance scaled to its size, and prints where to draw the coarse surface and the
// fine truth beside the enriched one: two lines, ~marker_coarse_offset then ~marker_fine_offset ("[x, y, z]"
// in metres: one surface width and a margin towards -y, and towards +y).
#include <CLI/CLI.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <regex>
#include <sstream>

#include "deformation_enrichment/atomic_file.hpp"
#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/scene_file/scene_description.hpp"
#include "deformation_enrichment/scenes/scene_models.hpp"
#include "command_line.hpp"

using namespace deformation_enrichment;

int main(int argc, char** argv) {
  CLI::App app{"Writes an rviz config whose camera frames a scene's display surface, prints the coarse and fine offsets"};
  std::string sceneName, templatePath, outputPath;
  app.add_option("--scene", sceneName, "shipped scene name or scene file (.yaml)")->required();
  app.add_option("--rviz", templatePath, "rviz config to copy (its orbit view's angles are kept)")->required()->check(CLI::ExistingFile);
  app.add_option("--output", outputPath, "the rviz config to write")->required();
  if (const auto exitCode = deformation_enrichment::tools::parseCommandLine(app, argc, argv)) return *exitCode;
  try {
    const scenes::SceneGeometry geometry = scenes::sceneGeometry(scene_file::readSceneFile(scene_file::findSceneFile(sceneName)));
    const Eigen::Vector3d lo = geometry.surface.vertices.rowwise().minCoeff(), hi = geometry.surface.vertices.rowwise().maxCoeff();
    const Eigen::Vector3d extent = hi - lo;
    // The coarse surface and the fine truth one width and 5 % either side of the enriched one; the camera on
    // the middle one (a tenth of its width to the right, for the colour bar beyond the fine truth), as far as
    // the shipped view is from the three 10 cm slabs, scaled to this surface.
    const Eigen::Vector3d coarseOffset(0.0, -1.05 * extent.y(), 0.0), fineOffset(0.0, 1.05 * extent.y(), 0.0);
    const Eigen::Vector3d focus = 0.5 * (lo + hi) + Eigen::Vector3d(0.0, 0.1 * extent.y(), 0.0);
    const double distance = 0.33 * std::max(extent.x(), extent.y()) / 0.10;
    std::ifstream in(templatePath);
    std::stringstream text;
    text << in.rdbuf();
    std::ostringstream focal, far;
    focal << "Focal Point: {X: " << focus.x() << ", Y: " << focus.y() << ", Z: " << focus.z() << "}";
    far << "Distance: " << distance;
    std::string rviz = std::regex_replace(text.str(), std::regex("Focal Point: \\{[^}]*\\}"), focal.str());
    rviz = std::regex_replace(rviz, std::regex("Distance: [-0-9.eE+]+"), far.str());
    writeFileAtomically(outputPath, rviz);
    for (const Eigen::Vector3d& o : {coarseOffset, fineOffset}) std::printf("[%g, %g, %g]\n", o.x(), o.y(), o.z());
  } catch (const std::exception& e) {
    std::cerr << "de_scene_view: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
