#include <gtest/gtest.h>

#include <map>
#include <set>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/grid_tet_mesh.hpp"
#include "deformation_enrichment/mesh/tet_refinement.hpp"
#include "deformation_enrichment/mesh/tet_surface.hpp"

using namespace deformation_enrichment;

namespace {

// Every face of a conforming mesh belongs to one tet (boundary) or two (interior), never more.
void expectConforming(const mesh::TetMesh& m) {
  std::map<std::set<int>, int> faces;
  for (Eigen::Index t = 0; t < m.numTets(); ++t)
    for (int skip = 0; skip < 4; ++skip) {
      std::set<int> face;
      for (int k = 0; k < 4; ++k)
        if (k != skip) face.insert(m.tets(k, t));
      ++faces[face];
    }
  for (const auto& [face, count] : faces) EXPECT_LE(count, 2);
}

}  // namespace

TEST(TetRefinement, EachTetBecomesEightThatFillItExactly) {
  const mesh::TetMesh coarse = mesh::gridTetMesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(2.0, 1.0, 0.5), Eigen::Vector3i(2, 2, 1));
  for (int levels : {0, 1, 2}) {
    SCOPED_TRACE(levels);
    const mesh::TetMesh fine = mesh::refineTets(coarse, levels);
    EXPECT_EQ(fine.numTets(), coarse.numTets() << (3 * levels));
    EXPECT_NO_THROW(mesh::validate(fine));  // every child positively oriented
    EXPECT_NEAR(mesh::totalVolume(fine), 1.0, 1e-12);
    EXPECT_EQ(fine.vertices.leftCols(coarse.numVertices()), coarse.vertices);
    expectConforming(fine);
    // The boundary is the same box: its area is unchanged and no boundary node lies inside.
    const mesh::TetSurface boundary = mesh::extractSurface(fine);
    for (int v : boundary.surfaceToVolume) {
      const Eigen::Vector3d x = fine.vertices.col(v);
      const bool onFace = (x.array() == 0.0).any() || x.x() == 2.0 || x.y() == 1.0 || x.z() == 0.5;
      EXPECT_TRUE(onFace) << x.transpose();
    }
  }
}

TEST(TetRefinement, LevelsReachTheRequestedVolume) {
  const mesh::TetMesh coarse = mesh::gridTetMesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 1, 1), Eigen::Vector3i(1, 1, 1));  // 6 tets of 1/6
  EXPECT_EQ(mesh::refinementLevels(coarse, 1.0), 0);
  EXPECT_EQ(mesh::refinementLevels(coarse, 1.0 / 6.0 / 8.0), 1);
  EXPECT_EQ(mesh::refinementLevels(coarse, 1.0 / 6.0 / 9.0), 2);
  EXPECT_THROW(mesh::refinementLevels(coarse, 0.0), InvalidInputError);
  EXPECT_THROW(mesh::refineTets(coarse, -1), InvalidInputError);
  mesh::TetMesh flat = coarse;
  flat.vertices.row(2).setZero();
  EXPECT_THROW(mesh::refineTets(flat), InvalidInputError);
}
