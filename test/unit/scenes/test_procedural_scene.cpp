#include <gtest/gtest.h>

#include <set>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/tet_surface.hpp"
#include "deformation_enrichment/scenes/procedural_scene.hpp"

using namespace deformation_enrichment;

namespace {
double skinVolume(const scenes::Scene& s) {
  double volume = 0.0;
  for (Eigen::Index t = 0; t < s.mesh.numTets(); ++t)
    if (s.materialId[t] == scenes::kSkinMaterial) volume += mesh::signedVolume(s.mesh, t);
  return volume;
}
}  // namespace

TEST(ProceduralScene, DefaultSlabMatchesSpecification) {
  const scenes::Scene slab = scenes::makeSlab();
  EXPECT_NO_THROW(mesh::validate(slab.mesh));
  EXPECT_NEAR(slab.mesh.vertices.row(0).minCoeff(), -0.05, 1e-15);
  EXPECT_NEAR(slab.mesh.vertices.row(0).maxCoeff(), 0.05, 1e-15);
  EXPECT_NEAR(slab.mesh.vertices.row(2).minCoeff(), 0.0, 1e-15);
  EXPECT_NEAR(slab.mesh.vertices.row(2).maxCoeff(), 0.02, 1e-15);
  EXPECT_NEAR(mesh::totalVolume(slab.mesh), 0.1 * 0.1 * 0.02, 1e-15);
  EXPECT_NEAR(skinVolume(slab), 0.1 * 0.1 * 0.001, 1e-15);  // the skin is exactly the top millimetre
  EXPECT_EQ(slab.mesh.numTets(), 20 * 20 * 5 * 6);
  for (int v : slab.fixedVertices) EXPECT_EQ(slab.mesh.vertices(2, v), 0.0);
  for (int v : slab.topVertices) EXPECT_NEAR(slab.mesh.vertices(2, v), 0.02, 1e-15);
  EXPECT_EQ(slab.fixedVertices.size(), 21u * 21u);
  EXPECT_EQ(slab.topVertices.size(), 21u * 21u);

  scenes::SlabOptions bare;
  bare.layering.skinThickness = 0.0;
  const scenes::Scene noSkin = scenes::makeSlab(bare);
  EXPECT_EQ(noSkin.materialId.maxCoeff(), scenes::kBulkMaterial);
  EXPECT_EQ(noSkin.mesh.numTets(), 20 * 20 * 4 * 6);
}

TEST(ProceduralScene, PillowAndMeniscusAreValidClosedVolumes) {
  const scenes::Scene pillow = scenes::makePillow();
  EXPECT_NO_THROW(mesh::validate(pillow.mesh));
  EXPECT_NEAR(pillow.mesh.vertices.row(2).maxCoeff(), 0.03, 1e-12);
  EXPECT_GT(skinVolume(pillow), 0.0);
  // Volume of the bulged box: integral of the top height over the footprint = 4 a b (e + (h - e) 4/9);
  // the tets interpolate the height linearly, so allow the discretisation error.
  const double exact = 4 * 0.05 * 0.04 * (0.008 + 0.022 * 4.0 / 9.0);
  EXPECT_NEAR(mesh::totalVolume(pillow.mesh), exact, 0.02 * exact);

  const scenes::Scene meniscus = scenes::makeMeniscus();
  EXPECT_NO_THROW(mesh::validate(meniscus.mesh));
  // Each boundary face belongs to one tet: a closed 2-manifold has Euler characteristic 2.
  const mesh::TetSurface surface = mesh::extractSurface(meniscus.mesh);
  std::set<std::pair<int, int>> edges;
  for (Eigen::Index f = 0; f < surface.surface.numTriangles(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = surface.surface.triangles(k, f), b = surface.surface.triangles((k + 1) % 3, f);
      edges.insert({std::min(a, b), std::max(a, b)});
    }
  EXPECT_EQ(surface.surface.numVertices() - static_cast<Eigen::Index>(edges.size()) + surface.surface.numTriangles(), 2);
  std::set<int> fixed(meniscus.fixedVertices.begin(), meniscus.fixedVertices.end());
  for (int v : meniscus.topVertices) EXPECT_EQ(fixed.count(v), 0u);
  EXPECT_GT(meniscus.fixedVertices.size(), 25u * 7u);
}

TEST(ProceduralScene, RejectsBadOptionsAndFindsNearVertices) {
  scenes::SlabOptions bad;
  bad.layering.skinThickness = 0.05;
  EXPECT_THROW(scenes::makeSlab(bad), InvalidInputError);
  bad = scenes::SlabOptions();
  bad.layering.cells = Eigen::Vector3i(0, 2, 2);
  EXPECT_THROW(scenes::makeSlab(bad), InvalidInputError);
  scenes::MeniscusOptions wrap;
  wrap.endAngle = 7.0;
  EXPECT_THROW(scenes::makeMeniscus(wrap), InvalidInputError);
  const scenes::Scene slab = scenes::makeSlab();
  const auto near = scenes::verticesNear(slab.mesh, slab.topVertices, Eigen::Vector3d(0, 0, 0.02), 0.0051);
  EXPECT_EQ(near.size(), 5u);  // the centre and its four grid neighbours at 5 mm
}
