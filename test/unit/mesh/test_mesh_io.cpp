#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <vector>

#include "cgal_data.hpp"

#include "../missing_input.hpp"
#include "deformation_enrichment/error.hpp"
#include "expect_io_error.hpp"
#include "deformation_enrichment/mesh/grid_tet_mesh.hpp"
#include "deformation_enrichment/mesh/mesh_io.hpp"
#include "deformation_enrichment/mesh/surface_report.hpp"
#include "deformation_enrichment/mesh/tet_surface.hpp"

using namespace deformation_enrichment;

namespace {
std::string tempPath(const std::string& name) { return ::testing::TempDir() + "de_mesh_io_" + name; }

mesh::TriangleMesh boxSurface() {
  return mesh::extractSurface(
             mesh::gridTetMesh(Eigen::Vector3d(-0.05, -0.05, 0), Eigen::Vector3d(0.05, 0.05, 0.02), Eigen::Vector3i(4, 4, 2)))
      .surface;
}
}  // namespace

TEST(MeshIo, ObjAndPlyRoundTripKeepTopologyAndFloatPositions) {
  const mesh::TriangleMesh box = boxSurface();
  for (const std::string name : {"box.obj", "box.ply"}) {
    const std::string path = tempPath(name);
    mesh::writeTriangleMesh(path, box);
    const mesh::TriangleMesh back = mesh::readTriangleMesh(path);
    ASSERT_EQ(back.numVertices(), box.numVertices()) << name;
    ASSERT_EQ(back.triangles, box.triangles) << name;
    EXPECT_LT((back.vertices - box.vertices).cwiseAbs().maxCoeff(), 1e-7) << name;  // stored as float32
    std::remove(path.c_str());
  }
}

TEST(MeshIo, ReadsAssimpTestModels) {
  // Real files nobody here wrote (Debian assimp-testmodels): quads are split into two triangles each.
  const std::string dir = "/usr/share/assimp/models/";
  if (!std::ifstream(dir + "PLY/cube.ply").good()) DE_MISSING_INPUT("assimp-testmodels is not installed");
  const mesh::TriangleMesh cube = mesh::readTriangleMesh(dir + "PLY/cube.ply");
  EXPECT_EQ(cube.numTriangles(), 12);
  EXPECT_NO_THROW(mesh::validate(cube, false));
  const mesh::TriangleMesh binary = mesh::readTriangleMesh(dir + "PLY/cube_binary.ply");
  EXPECT_EQ(binary.numTriangles(), 12);
  const mesh::TriangleMesh wuson = mesh::readTriangleMesh(dir + "OBJ/WusonOBJ.obj");
  EXPECT_GT(wuson.numTriangles(), 1000);
  EXPECT_NO_THROW(mesh::validate(wuson, false));
}

TEST(MeshIo, CorruptMissingAndFacelessFilesGiveIoError) {
  EXPECT_THROW(mesh::readTriangleMesh(tempPath("missing.obj")), IoError);
  EXPECT_THROW(mesh::readTriangleMesh(tempPath("mesh.stl")), IoError);
  EXPECT_THROW(mesh::readTriangleMesh(tempPath("mesh.vrml")), IoError);
  const std::string corrupt = tempPath("corrupt.ply");
  std::ofstream(corrupt) << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nend_header\n1\n";
  EXPECT_THROW(mesh::readTriangleMesh(corrupt), IoError);
  const std::string outOfRange = tempPath("range.obj");
  std::ofstream(outOfRange) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n";
  EXPECT_THROW(mesh::readTriangleMesh(outOfRange), IoError);
  const std::string points = tempPath("points.obj");
  std::ofstream(points) << "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  EXPECT_THROW(mesh::readTriangleMesh(points), IoError);
  for (const auto& p : {corrupt, outOfRange, points}) std::remove(p.c_str());
}

namespace {
/// Binary STL bytes: 80-byte header, facet count, per facet a normal, three corners and two spare bytes.
std::string binaryStl(const std::vector<std::array<float, 9>>& facets, const char* header = "written by the test") {
  std::string bytes(80, ' ');
  std::memcpy(bytes.data(), header, std::strlen(header));
  const std::uint32_t count = static_cast<std::uint32_t>(facets.size());
  bytes.append(reinterpret_cast<const char*>(&count), 4);
  for (const auto& facet : facets) {
    const float normal[3] = {0, 0, 0};
    bytes.append(reinterpret_cast<const char*>(normal), 12);
    bytes.append(reinterpret_cast<const char*>(facet.data()), 36);
    bytes.append(2, '\0');
  }
  return bytes;
}

const std::vector<std::array<float, 9>> kTetFacets = {{0, 0, 0, 0, 1, 0, 1, 0, 0}, {0, 0, 0, 1, 0, 0, 0, 0, 1},
                                                      {0, 0, 0, 0, 0, 1, 0, 1, 0}, {1, 0, 0, 0, 1, 0, 0, 0, 1}};

}  // namespace

TEST(MeshIo, ReadsCgalOffAndStlMeshes) {
  DE_REQUIRE_CGAL_DATA();
  const std::string dir = test::CgalData::dir() + "data/meshes/";
  const mesh::TriangleMesh femur = mesh::readTriangleMesh(dir + "femur.off");  // header: 3897 7798 0
  EXPECT_EQ(femur.numVertices(), 3897);
  EXPECT_EQ(femur.numTriangles(), 7798);
  EXPECT_TRUE(mesh::inspectSurface(femur).closedManifold()) << mesh::describe(mesh::inspectSurface(femur));
  const mesh::TriangleMesh quads = mesh::readTriangleMesh(dir + "cube_quad.off");  // 6 quads -> 12 triangles
  EXPECT_EQ(quads.numVertices(), 8);
  EXPECT_EQ(quads.numTriangles(), 12);
  EXPECT_TRUE(mesh::inspectSurface(quads).closedManifold());
  // Binary STL stores every corner per facet: CGAL merges identical corners, which closes the surface.
  const mesh::TriangleMesh sphereStl = mesh::readTriangleMesh(dir + "sphere.stl");
  const mesh::SurfaceReport sphere = mesh::inspectSurface(sphereStl);
  EXPECT_EQ(sphere.triangles, (16084 - 84) / 50);
  EXPECT_TRUE(sphere.closedManifold()) << mesh::describe(sphere);
  EXPECT_EQ(sphere.duplicateVertices, 0);
  EXPECT_EQ(2 * sphere.vertices - 4, sphere.triangles);  // Euler: a closed genus-0 triangle mesh
  const mesh::TriangleMesh pig = mesh::readTriangleMesh(dir + "pig.stl");
  EXPECT_EQ(pig.numTriangles(), (842484 - 84) / 50);
  EXPECT_NO_THROW(mesh::validate(pig, false));
}

TEST(MeshIo, StlAsciiAndBinaryFromStreamsAndFiles) {
  const std::string ascii =
      "solid tet\n"
      "facet normal 0 0 -1\n outer loop\n  vertex 0 0 0\n  vertex 0 1 0\n  vertex 1 0 0\n endloop\nendfacet\n"
      "facet normal 0 -1 0\n outer loop\n  vertex 0 0 0\n  vertex 1 0 0\n  vertex 0 0 1\n endloop\nendfacet\n"
      "facet normal -1 0 0\n outer loop\n  vertex 0 0 0\n  vertex 0 0 1\n  vertex 0 1 0\n endloop\nendfacet\n"
      "facet normal 1 1 1\n outer loop\n  vertex 1 0 0\n  vertex 0 1 0\n  vertex 0 0 1\n endloop\nendfacet\n"
      "endsolid tet\n";
  for (const std::string& bytes : {ascii, binaryStl(kTetFacets), binaryStl(kTetFacets, "solid but binary")}) {
    std::istringstream in(bytes, std::ios::binary);
    const mesh::TriangleMesh tet = mesh::readTriangleMesh(in, mesh::SurfaceFormat::Stl, "tet.stl");
    EXPECT_EQ(tet.numVertices(), 4);  // corners merged in order of first use
    EXPECT_EQ(tet.vertices.col(1), Eigen::Vector3d(0, 1, 0));
    const mesh::SurfaceReport report = mesh::inspectSurface(tet);
    EXPECT_TRUE(report.closedManifold()) << mesh::describe(report);
  }
  const std::string path = tempPath("tet.stl");
  std::ofstream(path, std::ios::binary) << binaryStl(kTetFacets);
  EXPECT_EQ(mesh::readTriangleMesh(path).numTriangles(), 4);
  std::remove(path.c_str());
}

TEST(MeshIo, CorruptOffAndStlNameFileAndPosition) {
  const auto readOff = [](const std::string& text) {
    return [text] {
      std::istringstream in(text);
      mesh::readTriangleMesh(in, mesh::SurfaceFormat::Off, "bad.off");
    };
  };
  test::expectIoError(readOff("OFF\n3 1 0\n0 0 0\n1 0 0\n"), {"bad.off", "OFF", "line"});
  test::expectIoError(readOff("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n"), {"bad.off", "line 6"});
  test::expectIoError(readOff("OFF\n3 1 0\n0 0 0\n1 0 x\n0 1 0\n3 0 1 2\n"), {"bad.off", "line 4"});
  test::expectIoError(readOff("OFF\n3 0 0\n0 0 0\n1 0 0\n0 1 0\n"), {"bad.off", "no triangles"});
  // Found by fuzz_off_stl in CGAL's scanner (memory blow-up, casts of out-of-range doubles, reads past a
  // COFF vertex line): each is a message now.
  test::expectIoError(readOff("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n888888888 0 1 2\n"), {"bad.off", "line 6", "corner count"});
  test::expectIoError(readOff("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3.2e37 0 1 2\n"), {"bad.off", "line 6", "corner count"});
  test::expectIoError(readOff("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 -4 2\n"), {"bad.off", "line 6", "vertex index"});
  test::expectIoError(readOff("COFF\n3 4 0\n0\n"), {"bad.off", "line 3", "vertex coordinate"});
  test::expectIoError(readOff("OFF\n99999999999 1 0\n"), {"bad.off", "ends before vertex"});
  test::expectIoError(readOff("OFF BINARY\n"), {"bad.off", "binary OFF"});
  test::expectIoError(readOff("nOFF\n3\n"), {"bad.off", "nOFF"});
  // Variants read as CGAL reads them: counts on the keyword line, colours and comments ignored, 4OFF divided.
  for (const std::string text : {"OFF 3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
                                 "# c\nCOFF\n3 1 0\n0 0 0 1 0 0\n1 0 0 0 1 0 1\n0 1 0 .5 .5 .5\n3 0 1 2 255 0 0 # red\n",
                                 "4OFF\n3 1 0\n0 0 0 2\n2 0 0 2\n0 2 0 2\n3 0 1 2\n"}) {
    std::istringstream in(text);
    const mesh::TriangleMesh m = mesh::readTriangleMesh(in, mesh::SurfaceFormat::Off, "ok.off");
    ASSERT_EQ(m.numTriangles(), 1) << text;
    EXPECT_EQ(m.vertices.col(1), Eigen::Vector3d(1, 0, 0)) << text;
  }
  std::string truncated = binaryStl(kTetFacets);
  truncated.resize(truncated.size() - 30);
  test::expectIoError(
      [&] {
        std::istringstream in(truncated, std::ios::binary);
        mesh::readTriangleMesh(in, mesh::SurfaceFormat::Stl, "cut.stl");
      },
      {"cut.stl", "STL", "byte"});
  // OBJ and PLY streams go to the core's readers: a file without faces is refused naming the source.
  std::istringstream faceless("v 0 0 0\n");
  EXPECT_THROW(mesh::readTriangleMesh(faceless, mesh::SurfaceFormat::Obj, "x.obj"), IoError);
  std::istringstream triangle("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  EXPECT_EQ(mesh::readTriangleMesh(triangle, mesh::SurfaceFormat::Obj, "t.obj").numTriangles(), 1);
}

TEST(SurfaceReport, CountsDuplicatesDegenerateOpenAndNonManifoldEdges) {
  std::istringstream in(
      "OFF\n7 5 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n1 0 0\n2 0 0\n5 5 5\n"
      "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 0 1 5\n3 0 4 1\n");  // open tet, a fin on edge 0-1, a flat triangle
  const mesh::TriangleMesh mesh = mesh::readTriangleMesh(in, mesh::SurfaceFormat::Off, "report.off");
  const mesh::SurfaceReport report = mesh::inspectSurface(mesh);
  EXPECT_EQ(report.duplicateVertices, 1);    // vertex 4 sits on vertex 1
  EXPECT_EQ(report.unusedVertices, 1);       // vertex 6
  EXPECT_EQ(report.degenerateTriangles, 2);  // (0, 1, 5) collinear, (0, 4, 1) coincident corners
  EXPECT_EQ(report.nonManifoldEdges, 0);
  EXPECT_EQ(report.boundaryEdges, 3);        // the missing face's edges
  EXPECT_FALSE(report.closedManifold());
  mesh::TriangleMesh closed = mesh;
  closed.triangles.col(3) << 1, 2, 3;  // the missing face: a closed tet (plus the flat triangle)
  EXPECT_TRUE(mesh::inspectSurface(closed).closedManifold()) << mesh::describe(mesh::inspectSurface(closed));
  mesh::TriangleMesh flipped = closed;
  flipped.triangles.col(3) << 1, 3, 2;
  EXPECT_EQ(mesh::inspectSurface(flipped).misorientedEdges, 3);
  mesh::TriangleMesh fin = mesh;
  fin.triangles.col(3) << 0, 1, 2;  // a third triangle on edges 0-1 and 0-2
  const mesh::SurfaceReport finReport = mesh::inspectSurface(fin);
  EXPECT_EQ(finReport.nonManifoldEdges, 2);
  EXPECT_EQ(finReport.boundaryEdges, 2);
  EXPECT_NE(mesh::describe(report).find("2 zero-area triangles"), std::string::npos) << mesh::describe(report);
}
