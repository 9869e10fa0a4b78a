#include <gtest/gtest.h>

#include <cstdio>
#include <unistd.h>
#include <fstream>
#include <sstream>
#include <string>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/grid_tet_mesh.hpp"
#include "deformation_enrichment/mesh/tetgen_io.hpp"
#include "../expect_error.hpp"

using namespace deformation_enrichment;

namespace {
std::string tempBase(const std::string& name) {
  return testing::TempDir() + "de_tetgen_" + name + "_" + std::to_string(::getpid());
}

void writeFile(const std::string& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
}

/// Expects readTetGen(base) to throw IoError whose message contains every fragment.
void expectIoError(const std::string& base, const std::vector<std::string>& fragments) {
  try {
    mesh::readTetGen(base);
    ADD_FAILURE() << "no error for " << base;
  } catch (const IoError& error) {
    for (const auto& fragment : fragments) EXPECT_NE(std::string(error.what()).find(fragment), std::string::npos) << error.what();
  }
}

const char* kNode = "# unit tet\n4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1  # apex\n";
}  // namespace

TEST(TetGenIo, RoundTripKeepsGeometryAndRegions) {
  const mesh::TetMesh grid = mesh::gridTetMesh(Eigen::Vector3d(-0.1, 0.0, 0.2), Eigen::Vector3d(0.3, 0.1, 0.25),
                                               Eigen::Vector3i(3, 2, 2));
  Eigen::VectorXi region(grid.numTets());
  for (Eigen::Index t = 0; t < region.size(); ++t) region[t] = static_cast<int>(t % 3);
  const std::string base = tempBase("roundtrip");
  mesh::writeTetGen(base, grid, region);
  const mesh::TetGenMesh read = mesh::readTetGen(base);
  EXPECT_EQ(read.mesh.tets, grid.tets);
  EXPECT_EQ(read.region, region);
  EXPECT_EQ(read.reorientedTets, 0);
  EXPECT_EQ((read.mesh.vertices - grid.vertices).cwiseAbs().maxCoeff(), 0.0);  // 17 digits: exact
}

TEST(TetGenIo, OneBasedNegativeOrientationAndTenNodeTets) {
  const std::string base = tempBase("onebased");
  writeFile(base + ".node", kNode);
  // 10-node elements reference mid-edge nodes we do not have: give them existing indices (only corners are read).
  writeFile(base + ".ele", "1 10 1\n1  1 3 2 4  1 1 1 1 1 1  7\n");
  const mesh::TetGenMesh read = mesh::readTetGen(base);
  EXPECT_EQ(read.reorientedTets, 1);
  EXPECT_EQ(read.region[0], 7);
  EXPECT_GT(mesh::signedVolume(read.mesh, 0), 0.0);
  EXPECT_NO_THROW(mesh::validate(read.mesh));
}

TEST(TetGenIo, CorruptFilesNameFileAndLine) {
  const std::string base = tempBase("corrupt");
  writeFile(base + ".node", kNode);
  writeFile(base + ".ele", "1 4 0\n1 1 2 3 9\n");
  expectIoError(base, {".ele:2", "out of range"});
  writeFile(base + ".ele", "1 4 0\n1 1 2 3 3\n");
  expectIoError(base, {".ele:2", "repeated"});
  writeFile(base + ".ele", "1 4 0\n1 1 2 3\n");
  expectIoError(base, {".ele:2", "fields"});
  writeFile(base + ".ele", "2 4 0\n1 1 2 3 4\n");
  expectIoError(base, {".ele", "ends", "tetrahedron 1"});
  writeFile(base + ".ele", "1 4 0\n1 1 2 x 4\n");
  expectIoError(base, {".ele:2", "'x'"});
  writeFile(base + ".node", "4 3 0 0\n1 0 0 0\n2 1 0 0\n3 2 0 0\n4 3 0 0\n");  // collinear: zero volume
  writeFile(base + ".ele", "1 4 0\n1 1 2 3 4\n");
  expectIoError(base, {".ele:2", "zero volume"});
  writeFile(base + ".node", "4 3 0 0\n1 0 0 0\n2 1 0 nan\n3 0 1 0\n4 0 0 1\n");
  expectIoError(base, {".node:3", "not finite"});
  writeFile(base + ".node", "4 2 0 0\n");
  expectIoError(base, {".node:1", "dimension"});
  writeFile(base + ".node", "4 3 0 0\n1 0 0 0\n3 1 0 0\n");
  expectIoError(base, {".node:3", "sequence"});
  expectIoError(tempBase("missing"), {"cannot open", ".node"});
}

TEST(TetGenIo, WriteRejectsBadRegionAndPath) {
  const mesh::TetMesh grid = mesh::gridTetMesh(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(), Eigen::Vector3i(1, 1, 1));
  EXPECT_THROW(mesh::writeTetGen(tempBase("bad"), grid, Eigen::VectorXi::Zero(2)), InvalidInputError);
  EXPECT_THROW(mesh::writeTetGen("/nonexistent_dir/x", grid), IoError);
}

TEST(TetGenIo, ReadsRealTetGenOutput) {
  // A 2 x 2 x 1 cm box meshed by Debian's tetgen 1.5.0 (1-based indices, its own orientation convention).
  const mesh::TetGenMesh read = mesh::readTetGen(std::string(DE_SOURCE_DIR) + "/test/data/tetgen/box.1");
  EXPECT_EQ(read.mesh.numVertices(), 46);
  EXPECT_EQ(read.mesh.numTets(), 80);
  EXPECT_NO_THROW(mesh::validate(read.mesh));
  double volume = 0.0;
  for (Eigen::Index t = 0; t < read.mesh.numTets(); ++t) volume += mesh::signedVolume(read.mesh, t);
  EXPECT_NEAR(volume, 0.02 * 0.02 * 0.01, 1e-18);
  // TetGen writes every tet with the same orientation: either all or none needed flipping.
  EXPECT_TRUE(read.reorientedTets == 0 || read.reorientedTets == 80) << read.reorientedTets;
  std::printf("tetgen tets reoriented: %d of 80\n", read.reorientedTets);
}

namespace {
/// readTetGen on in-memory texts must throw IoError whose message contains `fragment`.
void expectRejectedText(const std::string& node, const std::string& ele, const std::string& fragment) {
  std::istringstream nodeIn(node), eleIn(ele);
  expectErrorContaining<IoError>([&] { mesh::readTetGen(nodeIn, eleIn, "mem"); }, fragment);
}
}  // namespace

TEST(TetGenIo, StreamEntryPointReadsWhatTheFilesHold) {
  std::istringstream node(kNode), ele("1 4 0\n1 1 2 3 4\n");
  const mesh::TetGenMesh read = mesh::readTetGen(node, ele, "mem");
  EXPECT_EQ(read.mesh.numVertices(), 4);
  EXPECT_EQ(read.mesh.tets.col(0), Eigen::Vector4i(0, 1, 2, 3));
}

// Inputs the fuzzer (scripts/fuzz, fuzz_tetgen) or its review found; each was undefined behaviour, an
// unbounded allocation or a broken promise before.
TEST(TetGenIo, HostileCountsAndIndicesAreRejectedNotOverflowed) {
  const std::string ele = "1 4 0\n1 1 2 3 4\n";
  // Node index LONG_MIN: `index - base` overflowed.
  expectRejectedText(kNode, "1 4 0\n1 -9223372036854775808 2 3 4\n", "out of range");
  // Attribute counts near LONG_MAX: `4 + attributes + markers` overflowed.
  expectRejectedText("1 3 9223372036854775807 1\n1 0 0 0\n", ele, "expected 9223372036854775812");
  expectRejectedText(kNode, "1 4 9223372036854775807\n1 1 2 3 4\n", "expected 9223372036854775812");
  // A header that lies about the count: nothing is allocated for 10^18 points or tets up front.
  expectRejectedText("1000000000000000000 3 0 0\n1 0 0 0\n", ele, "point 1 is missing");
  expectRejectedText(kNode, "1000000000000000000 4 0\n1 1 2 3 4\n", "tetrahedron 1 is missing");
  // A region attribute outside int: lround gave an unspecified value.
  expectRejectedText(kNode, "1 4 1\n1 1 2 3 4 1e300\n", "outside the int range");
  // Coordinates so large that the volume overflows.
  expectRejectedText("4 3 0 0\n1 0 0 0\n2 1e200 0 0\n3 0 1e200 0\n4 0 0 1e200\n", ele, "not finite");
}

TEST(TetGenIo, TetWhoseOrientationIsLostInRoundingIsFlat) {
  // fuzz_tetgen: the determinant is negative, and after flipping the tet it is zero (the huge z
  // cancels), so readTetGen returned a tet that mesh::validate rejects as non-positive.
  const std::string node =
      "4 3 0 0\n1 0.01 0.01 0\n2 0.014166666666666668 0.0058333333333333336 0.01\n"
      "3 0.014166666666666668 0.0058333333333333336 0\n4 0 0 14166666666666666\n";
  expectRejectedText(node, "1 4 0\n1 1 2 3 4\n", "zero volume");
}
