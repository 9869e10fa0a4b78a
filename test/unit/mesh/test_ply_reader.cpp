// The core's PLY reader: ASCII and both binary byte orders, any coordinate type, and the content on which
// PCL's reader aborted the process (a vertex list property whose length changes, found by fuzz_ply) or
// trusted the header's counts.
#include <gtest/gtest.h>

#include <cstring>
#include <sstream>
#include <string>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/ply_reader.hpp"
#include "../expect_error.hpp"

using namespace deformation_enrichment;

namespace {

mesh::TriangleMesh readPlyBytes(const std::string& bytes) {
  std::istringstream in(bytes);
  return mesh::readPly(in, "mem.ply");
}

void expectPlyRejected(const std::string& text, const std::string& fragment) {
  expectErrorContaining<IoError>([&] { readPlyBytes(text); }, fragment);
}

template <class T>
std::string bytesOf(T value, bool bigEndian) {
  std::string b(sizeof value, '\0');
  std::memcpy(&b[0], &value, sizeof value);
  if (bigEndian) b = std::string(b.rbegin(), b.rend());
  return b;
}

const char* kVertexHeader = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n";
const char* kFaceHeader = "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
const char* kVertices = "0 0 0\n1 0 0\n0 1 0\n";

}  // namespace

TEST(PlyReader, AsciiWithExtraElementsPropertiesAndCrlf) {
  const mesh::TriangleMesh m = readPlyBytes(
      "ply\r\nformat ascii 1.0\r\ncomment c\r\nobj_info o\r\nelement vertex 4\r\nproperty uchar red\r\n"
      "property double z\r\nproperty float x\r\nproperty int y\r\nelement edge 1\r\nproperty int a\r\n"
      "element face 1\r\nproperty uchar flags\r\nproperty list uchar uint vertex_index\r\nend_header\r\n"
      "255 0.5 0 0\r\n0 0.5 1 0\r\n0 0.5 1 1\r\n0 0.5 0 1\r\n7\r\n3 4 0 1 2 3\r\n");
  ASSERT_EQ(m.numVertices(), 4);
  EXPECT_EQ(m.vertices.col(2), Eigen::Vector3d(1, 1, 0.5));
  ASSERT_EQ(m.numTriangles(), 2);
  EXPECT_EQ(m.triangles.col(1), Eigen::Vector3i(0, 2, 3));
}

TEST(PlyReader, BinaryBothByteOrdersAndDoubleCoordinates) {
  for (const bool big : {false, true}) {
    std::string ply = std::string("ply\nformat ") + (big ? "binary_big_endian" : "binary_little_endian") +
                      " 1.0\nelement vertex 3\nproperty double x\nproperty double y\nproperty double z\n"
                      "property short s\n" + kFaceHeader;
    const double xyz[3][3] = {{0.1, 0.2, 0.3}, {1.0, 0.0, 0.0}, {0.0, 1.0, 0.0}};
    for (const auto& v : xyz) {
      for (double c : v) ply += bytesOf(c, big);
      ply += bytesOf<short>(-7, big);
    }
    ply += bytesOf<unsigned char>(3, big) + bytesOf<int>(0, big) + bytesOf<int>(1, big) + bytesOf<int>(2, big);
    const mesh::TriangleMesh m = readPlyBytes(ply);
    EXPECT_EQ(m.vertices.col(0), Eigen::Vector3d(0.1, 0.2, 0.3)) << big;  // exact: no float32 detour
    EXPECT_EQ(m.triangles.col(0), Eigen::Vector3i(0, 1, 2)) << big;
  }
}

TEST(PlyReader, ContentPclAbortedOnIsReadPast) {
  // fuzz_ply: a vertex list property whose length changes from vertex to vertex hit PCL's assert(false).
  const mesh::TriangleMesh m = readPlyBytes(std::string(kVertexHeader) + "property list uchar float extra\n" +
                                    "property uchar alpha\n" + kFaceHeader +
                                    "0 0 0 1 9 255\n1 0 0 3 9 9 9 255\n0 1 0 0 255\n3 0 1 2\n");
  EXPECT_EQ(m.numVertices(), 3);
  EXPECT_EQ(m.vertices.col(1), Eigen::Vector3d(1, 0, 0));
  EXPECT_EQ(m.numTriangles(), 1);
}

TEST(PlyReader, LyingCountsCostNothingAndBadHeadersAreNamed) {
  // PCL resized its buffers from these counts before reading any data.
  expectPlyRejected("ply\nformat ascii 1.0\nelement vertex 1000000000000\nproperty float x\nproperty float y\n"
                 "property float z\nend_header\n0 0 0\n",
                 "data ends inside element 'vertex' 1");
  expectPlyRejected(std::string(kVertexHeader) + "element face 1\nproperty list uint int vertex_indices\nend_header\n" +
                     kVertices + "4294967295 0 1 2\n",
                 "data ends inside element 'face' 0");
  expectPlyRejected(std::string(kVertexHeader) + "element nothing 1000000000000000000\n" + kFaceHeader,
                 "element 'nothing' has instances but no properties");
  expectPlyRejected("plyx\n", "does not start with the line 'ply'");
  expectPlyRejected("ply\nformat ascii 2.0\n", "mem.ply:2: format line");
  expectPlyRejected("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproelement face 1\n",
                 "mem.ply:5: unknown header line 'proelement face 1'");
  expectPlyRejected("ply\nformat ascii 1.0\nproperty float x\n", "property before any element");
  expectPlyRejected("ply\nformat ascii 1.0\nelement vertex 1\nproperty float128 x\n", "unknown property type 'float128'");
  expectPlyRejected("ply\nformat ascii 1.0\nelement vertex 1\nproperty list float int x\n", "list count type 'float'");
  expectPlyRejected("ply\nformat ascii 1.0\nelement vertex -1\n", "element count '-1'");
  expectPlyRejected("ply\nformat ascii 1.0\nelement vertex 1\nelement vertex 1\n", "declared twice");
  expectPlyRejected(std::string(kVertexHeader) + "property float x\n", "property 'x' declared twice");
  expectPlyRejected(std::string(kVertexHeader), "file ends inside the header");
  expectPlyRejected("ply\nelement vertex 0\nend_header\n", "no format line");
}

TEST(PlyReader, BadDataIsNamed) {
  const std::string header = std::string(kVertexHeader) + kFaceHeader;
  expectPlyRejected(header + "0 0 0\n1 0 x\n", "element 'vertex' 1: 'x' is not a number");
  expectPlyRejected(header + "0 0 0\n1 0 inf\n0 1 0\n", "vertex 1 is not finite");
  expectPlyRejected(header + kVertices + "3 0 1 2.5\n", "'2.5' is not a int");
  expectPlyRejected(header + kVertices + "256 0 1 2\n", "'256' is not a uchar");
  expectPlyRejected(header + kVertices + "3 0 1 3\n", "references vertex 3 of 3");
  expectPlyRejected(header + kVertices + "2 0 1\n", "no triangles");
  expectPlyRejected("ply\nformat ascii 1.0\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n",
                 "no vertex element");
  expectPlyRejected("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n0 0\n",
                 "no scalar property 'z'");
  expectPlyRejected(std::string(kVertexHeader) + "element face 1\nproperty list uchar float vertex_indices\nend_header\n" +
                     kVertices + "3 0 1 2\n",
                 "face element has no integer vertex_indices list");
}
