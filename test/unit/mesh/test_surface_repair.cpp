#include <gtest/gtest.h>

#include <Eigen/LU>
#include <cmath>
#include <limits>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/grid_tet_mesh.hpp"
#include "deformation_enrichment/mesh/mesh_io.hpp"
#include "deformation_enrichment/mesh/surface_repair.hpp"
#include "deformation_enrichment/mesh/surface_report.hpp"
#include "deformation_enrichment/mesh/tet_surface.hpp"

using namespace deformation_enrichment;

namespace {

mesh::TriangleMesh box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, int cells = 3) {
  return mesh::extractSurface(mesh::gridTetMesh(lo, hi, Eigen::Vector3i(cells, cells, cells))).surface;
}

// Two surfaces written as one mesh (a file holding two pieces).
mesh::TriangleMesh joined(const mesh::TriangleMesh& a, const mesh::TriangleMesh& b) {
  mesh::TriangleMesh out;
  out.vertices.resize(3, a.numVertices() + b.numVertices());
  out.vertices << a.vertices, b.vertices;
  out.triangles.resize(3, a.numTriangles() + b.numTriangles());
  out.triangles << a.triangles, (b.triangles.array() + static_cast<int>(a.numVertices())).matrix();
  return out;
}

void expectFillable(const mesh::SurfaceRepair& repair) {
  EXPECT_TRUE(repair.report.closedAndSelfIntersectionFree()) << mesh::describe(repair.report);
  EXPECT_TRUE(mesh::inspectSurface(repair.surface).closedManifold());
  EXPECT_EQ(mesh::countSelfIntersections(repair.surface), 0);
}

}  // namespace

TEST(SurfaceRepair, ACleanSurfaceIsKeptAsItIs) {
  const mesh::TriangleMesh cube = box(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 1, 1));
  EXPECT_EQ(mesh::countSelfIntersections(cube), 0);
  const mesh::SurfaceRepair repair = mesh::repairSurface(cube);
  EXPECT_TRUE(repair.report.untouched());
  EXPECT_EQ(repair.surface.vertices, cube.vertices);
  EXPECT_EQ(repair.surface.triangles, cube.triangles);
  EXPECT_EQ(mesh::describe(repair.report), "clean: nothing to repair");
}

TEST(SurfaceRepair, OverlappingPiecesBecomeTheirUnion) {
  // A unit cube and a box poking out of its side, in general position: no faces coplanar, no edge through
  // another piece's edge (the cube's faces are triangulated on a 1/3 grid).
  const mesh::TriangleMesh a = box(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 1, 1));
  const mesh::TriangleMesh b = box(Eigen::Vector3d(0.5, 0.21, 0.29), Eigen::Vector3d(1.5, 0.74, 0.88));
  const mesh::TriangleMesh both = joined(a, b);
  EXPECT_GT(mesh::countSelfIntersections(both), 0);
  const mesh::SurfaceRepair repair = mesh::repairSurface(both);
  expectFillable(repair);
  EXPECT_GT(repair.report.selfIntersections, 0);
  // Union: the unit cube plus the part of the second box outside it (0.5 x 0.53 x 0.59).
  EXPECT_NEAR(mesh::enclosedVolume(repair.surface), 1.0 + 0.5 * 0.53 * 0.59, 1e-9);
  EXPECT_NE(mesh::describe(repair.report).find("self-intersecting pairs"), std::string::npos);
}

TEST(SurfaceRepair, DuplicatesHolesInwardFacesAndDebrisAreRepaired) {
  mesh::TriangleMesh cube = box(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 1, 1));
  cube.triangles.row(1).swap(cube.triangles.row(2));  // every triangle faces inwards
  // A hole: the last triangle gone; a duplicate triangle; a zero-area triangle (three collinear corners).
  mesh::TriangleMesh dirty = cube;
  dirty.triangles.conservativeResize(3, cube.numTriangles() - 1);
  dirty.triangles.conservativeResize(3, dirty.numTriangles() + 1);
  dirty.triangles.col(dirty.numTriangles() - 1) = dirty.triangles.col(0);
  const int a = dirty.triangles(0, 0), b = dirty.triangles(1, 0), middle = static_cast<int>(dirty.numVertices());
  dirty.vertices.conservativeResize(3, middle + 1);
  dirty.vertices.col(middle) = 0.5 * (dirty.vertices.col(a) + dirty.vertices.col(b));
  dirty.triangles.conservativeResize(3, dirty.numTriangles() + 1);
  dirty.triangles.col(dirty.numTriangles() - 1) = Eigen::Vector3i(a, middle, b);
  // Debris: a tiny separate box far away.
  mesh::TriangleMesh speck = box(Eigen::Vector3d(5, 5, 5), Eigen::Vector3d(5.01, 5.01, 5.01), 1);
  dirty = joined(dirty, speck);
  const mesh::SurfaceRepair repair = mesh::repairSurface(dirty);
  expectFillable(repair);
  EXPECT_EQ(repair.report.holesFilled, 1);
  EXPECT_EQ(repair.report.droppedComponents, 1);
  EXPECT_EQ(repair.report.removedTriangles, 2);  // the duplicate and the zero-area one
  EXPECT_EQ(repair.report.mergedVertices, 1);   // the zero-area triangle's middle vertex, then unused
  EXPECT_TRUE(repair.report.reoriented);
  EXPECT_NEAR(mesh::enclosedVolume(repair.surface), 1.0, 1e-9);
}

TEST(SurfaceRepair, TheShippedDirtySurfaceIsRepaired) {
  const mesh::TriangleMesh lobes = mesh::readTriangleMesh(std::string(DE_SOURCE_DIR) + "/test/data/dirty_surface/two_lobes.obj");
  const Eigen::Index crossings = mesh::countSelfIntersections(lobes);
  EXPECT_GT(crossings, 10);
  const mesh::SurfaceRepair repair = mesh::repairSurface(lobes);
  expectFillable(repair);
  EXPECT_EQ(repair.report.selfIntersections, crossings);
  // The union is larger than the larger lobe and smaller than both together (volumes of the polyhedra).
  const double volume = mesh::enclosedVolume(repair.surface);
  EXPECT_GT(volume, 4.0 / 3.0 * M_PI * 20 * 20 * 20 * 0.95);
  EXPECT_LT(volume, 4.0 / 3.0 * M_PI * (20 * 20 * 20 + 14 * 14 * 14));
}

TEST(SurfaceRepair, UnusableInputIsRefusedWithAReason) {
  EXPECT_THROW(mesh::repairSurface(mesh::TriangleMesh{}), InvalidInputError);
  mesh::TriangleMesh cube = box(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 1, 1));
  cube.vertices(0, 0) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(mesh::repairSurface(cube), InvalidInputError);
  EXPECT_THROW(mesh::countSelfIntersections(cube), InvalidInputError);
  mesh::TriangleMesh flat;  // every triangle has zero area
  flat.vertices = Eigen::Matrix3Xd::Zero(3, 3);
  flat.vertices.col(1) = Eigen::Vector3d(1, 0, 0);
  flat.vertices.col(2) = Eigen::Vector3d(2, 0, 0);
  flat.triangles = Eigen::Matrix3Xi(3, 1);
  flat.triangles << 0, 1, 2;
  EXPECT_THROW(mesh::repairSurface(flat), InvalidInputError);
}
