#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/grid_tet_mesh.hpp"
#include "deformation_enrichment/mesh/mesh_io.hpp"
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
  if (!std::ifstream(dir + "PLY/cube.ply").good()) GTEST_SKIP() << "assimp-testmodels not installed";
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
