#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/barycentric_embedding.hpp"
#include "deformation_enrichment/mesh/grid_tet_mesh.hpp"
#include "deformation_enrichment/mesh/surface_report.hpp"
#include "deformation_enrichment/mesh/tet_surface.hpp"
#include "deformation_enrichment/scene_file/scene_description.hpp"
#include "deformation_enrichment/scenes/fine_model.hpp"
#include "deformation_enrichment/scenes/scene_models.hpp"

using namespace deformation_enrichment;

namespace {

const std::string kLobes = std::string(DE_SOURCE_DIR) + "/test/data/dirty_surface/two_lobes.yaml";

scenes::DisplaySurface cubeSurface(bool fillable) {
  scenes::DisplaySurface display;
  display.surface = mesh::extractSurface(mesh::gridTetMesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0.04, 0.04, 0.04), Eigen::Vector3i(4, 4, 4))).surface;
  display.fillable = fillable;
  return display;
}

}  // namespace

TEST(FileSceneModels, ASelfIntersectingSurfaceIsRepairedAndFilled) {
  const scene_file::SceneDescription scene = scene_file::readSceneFile(kLobes);
  EXPECT_EQ(scene.fineMaxVolume, 0.0);  // no `fine` key: the default
  const scenes::SceneModels m = scenes::buildSceneModels(scene);
  EXPECT_NE(m.report.find("repaired: "), std::string::npos) << m.report;
  EXPECT_NE(m.report.find("closed, no self-intersection left"), std::string::npos) << m.report;
  EXPECT_NE(m.report.find("(default: a regular tet with the display surface's median edge)"), std::string::npos) << m.report;
  EXPECT_FALSE(m.surfaceOnFine.has_value());  // conforming: the fine model keeps the display vertices
  EXPECT_TRUE(mesh::inspectSurface(m.surface).closedManifold());
  ASSERT_EQ(m.surfaceToFine.size(), static_cast<std::size_t>(m.surface.numVertices()));
  for (std::size_t v = 0; v < m.surfaceToFine.size(); ++v)
    ASSERT_EQ(m.fine.mesh.vertices.col(m.surfaceToFine[v]), m.surface.vertices.col(static_cast<Eigen::Index>(v)));
  EXPECT_GE(m.fine.fixedVertices.size(), 3u);
  EXPECT_FALSE(m.fine.topVertices.empty());
  // The default fine resolution: most tets no larger than a regular tet with the surface's median edge (tetgen
  // -a bounds the tets it refines; those against the kept surface triangles may be larger).
  const double maxVolume = scenes::defaultFineMaxVolume(m.surface);
  std::vector<double> volumes;
  for (Eigen::Index t = 0; t < m.fine.mesh.numTets(); ++t) volumes.push_back(mesh::signedVolume(m.fine.mesh, t));
  std::nth_element(volumes.begin(), volumes.begin() + static_cast<long>(volumes.size() / 2), volumes.end());
  EXPECT_LE(volumes[volumes.size() / 2], maxVolume);
}

TEST(FileSceneModels, AnUnfillableSurfaceIsEmbeddedInTheRefinedCoarseVolume) {
  scene_file::SceneDescription scene;
  scene.surface = "cube.obj";
  scene.fineMaxVolume = 1e-7;  // the coarse grid's tets are 4e-7: one 1:8 round
  const scenes::DisplaySurface display = cubeSurface(false);
  const mesh::TetMesh coarse = mesh::gridTetMesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0.04, 0.04, 0.04), Eigen::Vector3i(3, 3, 3));
  const scenes::FineModel fine = scenes::buildFineModel(scene, display, coarse);
  EXPECT_EQ(fine.mesh.numTets(), 8 * coarse.numTets());
  ASSERT_TRUE(fine.surfaceOnFine.has_value());
  EXPECT_NE(fine.report.find("refined 1 times"), std::string::npos) << fine.report;
  EXPECT_NE(fine.report.find("could not be made closed"), std::string::npos) << fine.report;
  // The embedding reproduces the display surface from the fine nodes, and each display vertex's node is on the boundary.
  const Eigen::Matrix3Xd back = mesh::interpolate(*fine.surfaceOnFine, fine.mesh, fine.mesh.vertices);
  EXPECT_LT((back - display.surface.vertices).cwiseAbs().maxCoeff(), 1e-12);
  for (std::size_t v = 0; v < fine.surfaceToFine.size(); ++v)
    EXPECT_LT((fine.mesh.vertices.col(fine.surfaceToFine[v]) - display.surface.vertices.col(static_cast<Eigen::Index>(v))).norm(), 0.01);
}

TEST(FileSceneModels, WhenBothWaysFailTheErrorSaysWhy) {
  scene_file::SceneDescription scene;
  scene.surface = "cube.obj";
  scene.maxOutside = 0.001;
  scenes::DisplaySurface display = cubeSurface(false);
  display.surface.vertices.array() += 0.1;  // 10 cm away from the coarse volume
  const mesh::TetMesh coarse = mesh::gridTetMesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0.04, 0.04, 0.04), Eigen::Vector3i(2, 2, 2));
  try {
    scenes::buildFineModel(scene, display, coarse);
    FAIL() << "no error";
  } catch (const InvalidInputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("cube.obj: no fine model"), std::string::npos) << message;
    EXPECT_NE(message.find("could not be made closed"), std::string::npos) << message;
  }
}
