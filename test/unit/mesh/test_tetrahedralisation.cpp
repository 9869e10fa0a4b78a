#include <gtest/gtest.h>

#include <Eigen/LU>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <set>
#include <string>

#include "cgal_data.hpp"
#include "../missing_input.hpp"
#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/barycentric_embedding.hpp"
#include "deformation_enrichment/mesh/edge_collapse.hpp"
#include "deformation_enrichment/mesh/mesh_io.hpp"
#include "deformation_enrichment/mesh/surface_report.hpp"
#include "deformation_enrichment/mesh/tet_surface.hpp"
#include "deformation_enrichment/mesh/tetrahedralisation.hpp"

using namespace deformation_enrichment;

namespace {

bool haveTetgen() { return std::system("command -v tetgen > /dev/null") == 0; }

#define DE_REQUIRE_TETGEN() \
  if (!haveTetgen()) DE_MISSING_INPUT("Debian's tetgen is not installed")

/// A triangle as a sorted corner triple, to compare triangle sets regardless of rotation and winding.
std::set<std::array<int, 3>> triangleSet(const Eigen::Matrix3Xi& triangles, const std::vector<int>& map = {}) {
  std::set<std::array<int, 3>> set;
  for (Eigen::Index t = 0; t < triangles.cols(); ++t) {
    std::array<int, 3> corners;
    for (int k = 0; k < 3; ++k) corners[size_t(k)] = map.empty() ? triangles(k, t) : map[size_t(triangles(k, t))];
    std::sort(corners.begin(), corners.end());
    set.insert(corners);
  }
  return set;
}

/// The unit cube's 12 triangles over 8 corners (outward).
mesh::TriangleMesh cube() {
  mesh::TriangleMesh cube;
  cube.vertices.resize(3, 8);
  cube.vertices << 0, 1, 1, 0, 0, 1, 1, 0,  //
      0, 0, 1, 1, 0, 0, 1, 1,               //
      0, 0, 0, 0, 1, 1, 1, 1;
  cube.triangles.resize(3, 12);
  cube.triangles << 0, 0, 4, 4, 0, 0, 1, 1, 2, 2, 3, 3,  //
      3, 2, 5, 6, 1, 5, 2, 6, 3, 7, 0, 4,                //
      2, 1, 6, 7, 5, 4, 6, 5, 7, 6, 4, 7;
  return cube;
}

template <class Call>
std::string errorOf(Call call) {
  try {
    call();
  } catch (const InvalidInputError& error) {
    return error.what();
  }
  return "no InvalidInputError";
}

}  // namespace

TEST(Tetrahedralisation, KeepsTheSurfaceVerticesAndTrianglesOfCgalMeshes) {
  DE_REQUIRE_TETGEN();
  DE_REQUIRE_CGAL_DATA();
  for (const std::string name : {"sphere.off", "femur.off"}) {
    const mesh::TriangleMesh surface = mesh::readTriangleMesh(test::CgalData::dir() + "data/meshes/" + name);
    mesh::TetrahedraliseOptions options;
    options.radiusEdgeRatio = 1.5;
    const mesh::Tetrahedralisation fine = mesh::tetrahedralise(surface, options);
    EXPECT_EQ(fine.surfaceVertices, surface.numVertices());
    EXPECT_EQ(fine.mesh.vertices.leftCols(surface.numVertices()), surface.vertices) << name;  // exact
    EXPECT_GT(fine.mesh.numVertices(), surface.numVertices()) << name;  // -q adds interior points
    const mesh::TetSurface boundary = mesh::extractSurface(fine.mesh);
    EXPECT_EQ(triangleSet(boundary.surface.triangles, boundary.surfaceToVolume), triangleSet(surface.triangles)) << name;
    EXPECT_NEAR(mesh::totalVolume(fine.mesh), std::abs(mesh::enclosedVolume(surface)), 1e-9 * std::abs(mesh::enclosedVolume(surface))) << name;
    EXPECT_GT(fine.seconds, 0.0);
    EXPECT_EQ(fine.command, "-pzQFq1.5Y");
  }
}

TEST(Tetrahedralisation, VolumeLimitRefines) {
  DE_REQUIRE_TETGEN();
  mesh::TetrahedraliseOptions options;
  options.keepSurface = false;
  options.maxVolume = 0.001;
  const mesh::Tetrahedralisation refined = mesh::tetrahedralise(cube(), options);
  EXPECT_GE(refined.mesh.numTets(), 1000);
  for (Eigen::Index t = 0; t < refined.mesh.numTets(); ++t) EXPECT_LE(mesh::signedVolume(refined.mesh, t), 0.001 * (1 + 1e-9));
  EXPECT_NEAR(mesh::totalVolume(refined.mesh), 1.0, 1e-12);
  EXPECT_EQ(refined.surfaceVertices, 0);
}

TEST(Tetrahedralisation, SelfIntersectingNonManifoldAndOpenSurfacesAreRefused) {
  DE_REQUIRE_TETGEN();
  mesh::TriangleMesh crossed = cube();
  crossed.vertices.col(7) << 0.5, 0.5, -0.5;  // the top corner pushed through the bottom face
  const std::string intersecting = errorOf([&] { mesh::tetrahedralise(crossed); });
  EXPECT_NE(intersecting.find("tetgen"), std::string::npos) << intersecting;
  EXPECT_NE(intersecting.find("intersects facet"), std::string::npos) << intersecting;  // tetgen's own words

  mesh::TriangleMesh fin = cube();  // a third triangle on edge 0-1
  fin.vertices.conservativeResize(3, 9);
  fin.vertices.col(8) << 0.5, -1.0, -1.0;
  fin.triangles.conservativeResize(3, 13);
  fin.triangles.col(12) << 0, 1, 8;
  const std::string nonManifold = errorOf([&] { mesh::tetrahedralise(fin); });
  EXPECT_NE(nonManifold.find("1 non-manifold edges"), std::string::npos) << nonManifold;

  mesh::TriangleMesh open = cube();
  open.triangles.conservativeResize(3, 10);
  EXPECT_NE(errorOf([&] { mesh::tetrahedralise(open); }).find("4 boundary edges"), std::string::npos);

  mesh::TetrahedraliseOptions missing;
  missing.program = "no-such-tetgen";
  EXPECT_THROW(mesh::tetrahedralise(cube(), missing), IoError);
}

TEST(Tetrahedralisation, SimplifiedSurfaceIsAClosedSubsetOfTheInput) {
  DE_REQUIRE_CGAL_DATA();
  const mesh::TriangleMesh femur = mesh::readTriangleMesh(test::CgalData::dir() + "data/meshes/femur.off");
  const mesh::EdgeCollapse collapse = mesh::collapseEdges(femur.triangles, femur.vertices, {300, 0.02});
  EXPECT_LE(collapse.keptVertices.size(), 300u);
  EXPECT_GE(collapse.keptVertices.size(), 250u);
  const mesh::TriangleMesh simplified = mesh::simplifySurface(femur, {300, 0.02});
  EXPECT_TRUE(mesh::inspectSurface(simplified).closedManifold()) << mesh::describe(mesh::inspectSurface(simplified));
  for (size_t k = 0; k < collapse.keptVertices.size(); ++k)
    EXPECT_EQ(simplified.vertices.col(Eigen::Index(k)), femur.vertices.col(collapse.keptVertices[k]));
  EXPECT_NE(errorOf([&] { mesh::simplifySurface(femur, {3, 0.02}); }).find("target vertex count"), std::string::npos);
}

TEST(Tetrahedralisation, CoarseVolumeOfAThinBoneSimplifiesLessWhereTheCollapseFolds) {
  DE_REQUIRE_TETGEN();
  DE_REQUIRE_CGAL_DATA();
  // CGAL's femur folds through itself when collapsed to 300 vertices: the target grows until tetgen
  // accepts the surface.
  const mesh::TriangleMesh femur = mesh::readTriangleMesh(test::CgalData::dir() + "data/meshes/femur.off");
  mesh::CoarseVolumeOptions options;
  options.simplification = {300, 0.02, 0.0};
  const mesh::CoarseVolume volume = mesh::coarseVolume(femur, options);
  std::printf("femur coarse volume: target %d, %ld boundary vertices, %ld nodes, %ld tets, inflation %g, %.2f s\n",
              volume.targetVertices, long(volume.boundaryVertices), long(volume.volume.mesh.numVertices()),
              long(volume.volume.mesh.numTets()), volume.inflation, volume.volume.seconds);
  EXPECT_GT(volume.targetVertices, 300);
  EXPECT_LE(volume.boundaryVertices, volume.targetVertices);
  EXPECT_EQ(volume.boundary.numVertices(), volume.boundaryVertices);
  EXPECT_NO_THROW(mesh::validate(volume.volume.mesh));
  options.simplification.targetVertices = 3;
  EXPECT_NE(errorOf([&] { mesh::coarseVolume(femur, options); }).find("target vertex count"), std::string::npos);
}
