#include <gtest/gtest.h>

#include <limits>

#include <Eigen/Geometry>

#include "deformation_enrichment/all_finite.hpp"
#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/grid_tet_mesh.hpp"
#include "deformation_enrichment/mesh/mesh_state.hpp"
#include "deformation_enrichment/mesh/polygon_triangulation.hpp"
#include "deformation_enrichment/mesh/tet_mesh.hpp"
#include "deformation_enrichment/mesh/tet_surface.hpp"
#include "deformation_enrichment/mesh/triangle_mesh.hpp"

using namespace deformation_enrichment;

namespace {
mesh::TetMesh unitCornerTet() {
  mesh::TetMesh tet;
  tet.vertices.resize(3, 4);
  tet.vertices << 0, 1, 0, 0,  //
      0, 0, 1, 0,              //
      0, 0, 0, 1;
  tet.tets.resize(4, 1);
  tet.tets << 0, 1, 2, 3;
  return tet;
}
}  // namespace

TEST(TetMesh, VolumeAndLumpedVolumes) {
  const mesh::TetMesh tet = unitCornerTet();
  EXPECT_NEAR(mesh::signedVolume(tet, 0), 1.0 / 6.0, 1e-15);
  const Eigen::VectorXd lumped = mesh::lumpedVertexVolumes(tet);
  EXPECT_NEAR(lumped.sum(), 1.0 / 6.0, 1e-15);
  EXPECT_NEAR(lumped[2], 1.0 / 24.0, 1e-15);
  EXPECT_NO_THROW(mesh::validate(tet));
}

TEST(TetMesh, RejectsInvertedNaNAndOutOfRange) {
  mesh::TetMesh tet = unitCornerTet();
  std::swap(tet.tets(1, 0), tet.tets(2, 0));
  EXPECT_THROW(mesh::validate(tet), InvalidInputError);
  EXPECT_NO_THROW(mesh::validate(tet, false));
  tet = unitCornerTet();
  tet.vertices(0, 3) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(mesh::validate(tet), InvalidInputError);
  tet = unitCornerTet();
  tet.tets(3, 0) = 4;
  EXPECT_THROW(mesh::validate(tet), InvalidInputError);
  EXPECT_THROW(mesh::validate(mesh::TetMesh{}), InvalidInputError);
}

TEST(TriangleMesh, NormalsOfATetSurfacePointOutwards) {
  const mesh::TetMesh tet = unitCornerTet();
  mesh::TriangleMesh surface;
  surface.vertices = tet.vertices;
  surface.triangles.resize(3, 4);
  surface.triangles << 0, 0, 0, 1,  //
      2, 1, 3, 2,                   //
      1, 3, 2, 3;
  ASSERT_NO_THROW(mesh::validate(surface));
  const Eigen::Matrix3Xd normals = mesh::vertexNormals(surface);
  const Eigen::Vector3d centroid = tet.vertices.rowwise().mean();
  for (int v = 0; v < 4; ++v) {
    EXPECT_NEAR(normals.col(v).norm(), 1.0, 1e-12);
    EXPECT_GT(normals.col(v).dot(tet.vertices.col(v) - centroid), 0.0) << "vertex " << v;
  }
}

TEST(TriangleMesh, RejectsDegenerateTriangle) {
  mesh::TriangleMesh flat;
  flat.vertices.resize(3, 3);
  flat.vertices << 0, 1, 2,  //
      0, 0, 0,               //
      0, 0, 0;
  flat.triangles.resize(3, 1);
  flat.triangles << 0, 1, 2;
  EXPECT_THROW(mesh::validate(flat), InvalidInputError);
  EXPECT_NO_THROW(mesh::validate(flat, false));
}

TEST(GridTetMesh, PositiveVolumesSumToTheBoxAndGradedAxesWork) {
  Eigen::VectorXd xs(4), ys(3), zs(3);
  xs << 0.0, 0.1, 0.5, 2.0;
  ys << -1.0, 0.0, 1.0;
  zs << 0.0, 0.25, 0.5;
  const mesh::TetMesh grid = mesh::gridTetMesh(xs, ys, zs);
  ASSERT_NO_THROW(mesh::validate(grid));
  EXPECT_EQ(grid.numTets(), 6 * 3 * 2 * 2);
  double total = 0.0;
  for (Eigen::Index t = 0; t < grid.numTets(); ++t) total += mesh::signedVolume(grid, t);
  EXPECT_NEAR(total, 2.0 * 2.0 * 0.5, 1e-12);
  EXPECT_THROW(mesh::gridTetMesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 1, 1), Eigen::Vector3i(0, 1, 1)),
               InvalidInputError);
}

TEST(TetSurface, BoxSurfaceIsClosedOutwardAndHasTheBoxArea) {
  const mesh::TetMesh grid = mesh::gridTetMesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(2, 1, 1), Eigen::Vector3i(4, 2, 3));
  const mesh::TetSurface s = mesh::extractSurface(grid);
  ASSERT_NO_THROW(mesh::validate(s.surface));
  // Every interior grid vertex is excluded: 5*3*4 vertices, 3*1*2 interior ones.
  EXPECT_EQ(s.surface.numVertices(), 5 * 3 * 4 - 3 * 1 * 2);
  double area = 0.0, volume = 0.0;  // divergence theorem: closed, outward surface encloses the box volume
  for (Eigen::Index t = 0; t < s.surface.numTriangles(); ++t) {
    const Eigen::Vector3d a = s.surface.vertices.col(s.surface.triangles(0, t));
    const Eigen::Vector3d b = s.surface.vertices.col(s.surface.triangles(1, t));
    const Eigen::Vector3d c = s.surface.vertices.col(s.surface.triangles(2, t));
    area += 0.5 * (b - a).cross(c - a).norm();
    volume += a.dot(b.cross(c)) / 6.0;
  }
  EXPECT_NEAR(area, 2 * (2 * 1 + 2 * 1 + 1 * 1), 1e-12);
  EXPECT_NEAR(volume, 2.0, 1e-12);
  for (size_t v = 0; v < s.surfaceToVolume.size(); ++v)
    EXPECT_EQ(s.surface.vertices.col(v), grid.vertices.col(s.surfaceToVolume[v]));
}

TEST(MeshState, ChecksCountAndFiniteness) {
  Eigen::Matrix3Xf state = Eigen::Matrix3Xf::Zero(3, 5);
  EXPECT_NO_THROW(mesh::validateMeshState(state, 5));
  EXPECT_THROW(mesh::validateMeshState(state, 6), InvalidInputError);
  state(1, 3) = std::numeric_limits<float>::infinity();
  try {
    mesh::validateMeshState(state, 5);
    FAIL() << "an Inf coordinate was accepted";
  } catch (const InvalidInputError& e) {
    EXPECT_NE(std::string(e.what()).find("point 3"), std::string::npos) << e.what();
  }
}

TEST(MeshState, EveryNonFiniteValueAnywhereInTheBufferIsFound) {
  // The flat-buffer check (all_finite.hpp) against a NaN, +Inf or -Inf at every position, float and double,
  // and finite extremes that must pass (their products with 0 are 0).
  Eigen::Matrix3Xf state = Eigen::Matrix3Xf::Constant(3, 37, std::numeric_limits<float>::max());
  state(0, 0) = std::numeric_limits<float>::lowest();
  state(2, 36) = std::numeric_limits<float>::denorm_min();
  EXPECT_TRUE(allFiniteValues(state));
  EXPECT_TRUE(allFiniteValues(Eigen::Matrix3Xd(state.cast<double>())));
  for (const float bad : {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(),
                          -std::numeric_limits<float>::infinity()})
    for (Eigen::Index i = 0; i < state.size(); ++i) {
      Eigen::Matrix3Xf broken = state;
      broken.data()[i] = bad;
      EXPECT_FALSE(allFiniteValues(broken)) << i;
      EXPECT_FALSE(allFiniteValues(Eigen::Matrix3Xd(broken.cast<double>()))) << i;
      EXPECT_THROW(mesh::validateMeshState(broken, 37), InvalidInputError) << i;
    }
}

TEST(PolygonTriangulation, FansQuadsSkipsLinesAndRejectsBadIndices) {
  const std::vector<std::vector<int>> polygons{{0, 1, 2, 3}, {1, 2}, {3, 2, 4}};
  const auto identity = [](const std::vector<int>& p) -> const auto& { return p; };
  const Eigen::Matrix3Xi tris = mesh::fanTriangulate(polygons, 5, identity);
  ASSERT_EQ(tris.cols(), 3);
  EXPECT_EQ(tris.col(0), Eigen::Vector3i(0, 1, 2));
  EXPECT_EQ(tris.col(1), Eigen::Vector3i(0, 2, 3));
  EXPECT_EQ(tris.col(2), Eigen::Vector3i(3, 2, 4));
  EXPECT_THROW(mesh::fanTriangulate(polygons, 4, identity), InvalidInputError);
}
