// The core's OBJ reader: what it reads, what it skips, and the malformed statements PCL's reader
// mishandled (it indexed past short token lists and threw std::out_of_range, found by fuzz_obj).
#include <gtest/gtest.h>

#include <sstream>
#include <string>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/obj_reader.hpp"
#include "../expect_error.hpp"

using namespace deformation_enrichment;

namespace {

mesh::TriangleMesh readObjText(const std::string& text) {
  std::istringstream in(text);
  return mesh::readObj(in, "mem.obj");
}

void expectObjRejected(const std::string& text, const std::string& fragment) {
  expectErrorContaining<IoError>([&] { readObjText(text); }, fragment);
}

const char* kSquare = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n";

}  // namespace

TEST(ObjReader, ReadsVerticesAndFanTriangulatesEveryCornerForm) {
  const mesh::TriangleMesh m =
      readObjText(std::string("# square\r\n") + kSquare + "vt 0 0\nvn 0 0 1\nf 1/1/1 2/1/1 3//1 4/1\nf -4 -3 -1\n");
  ASSERT_EQ(m.numVertices(), 4);
  EXPECT_EQ(m.vertices.col(2), Eigen::Vector3d(1, 1, 0));
  ASSERT_EQ(m.numTriangles(), 3);
  EXPECT_EQ(m.triangles.col(0), Eigen::Vector3i(0, 1, 2));
  EXPECT_EQ(m.triangles.col(1), Eigen::Vector3i(0, 2, 3));
  EXPECT_EQ(m.triangles.col(2), Eigen::Vector3i(0, 1, 3));  // negative: counted back from the last vertex
}

TEST(ObjReader, SkipsStatementsItDoesNotNeedAndAcceptsForwardReferences) {
  // The first line is fuzz_obj's: PCL threw std::out_of_range on "mtllib" without a space.
  const mesh::TriangleMesh m = readObjText(
      "mtllib+none.mtl\nmtllib\nusemtl\ng\no x\ns off\nl 1 2\np 1\nvn 0 0 1\nvn 0 0 1\nvn 0 0 1\nvn 0 0 1\nvn 1 0 0\n"
      "f 1 2 3\nv 0 0 0 1\nv 1 0 0 0.5 0.5 0.5\nv 0 1 0\n");
  EXPECT_EQ(m.numVertices(), 3);  // more normals than vertices overflowed PCL's point buffer
  EXPECT_EQ(m.numTriangles(), 1);
}

TEST(ObjReader, MalformedStatementsNameTheLine) {
  expectObjRejected("v 0 0 0\nv 1 0\n", "mem.obj:2: vertex needs x y z");  // PCL read past the token list
  expectObjRejected("v 0 0 x\n", "mem.obj:1: vertex coordinate 'x' is not a number");
  expectObjRejected("v 0 0 1e999\n", "'1e999' is not a number");
  expectObjRejected("v 0 0 nan\n", "mem.obj:1: vertex coordinate is not finite");
  expectObjRejected(std::string(kSquare) + "f 1 2 x\n", "mem.obj:5: face corner 'x'");  // PCL: sscanf left it unset
  expectObjRejected(std::string(kSquare) + "f 1 2 0\n", "face corner '0'");
  expectObjRejected(std::string(kSquare) + "f 1 2 -5\n", "counts back past the first vertex");
  expectObjRejected(std::string(kSquare) + "f 1 2 99999999999\n", "out of range");
  expectObjRejected(std::string(kSquare) + "f 1 2 5\n", "references vertex 4 of 4");
  expectObjRejected("# nothing\n", "mem.obj: no vertices");
  expectObjRejected(std::string(kSquare) + "f 1 2\n", "mem.obj: no triangles");
}
