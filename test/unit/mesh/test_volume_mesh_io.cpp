#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "../missing_input.hpp"
#include "deformation_enrichment/error.hpp"
#include "expect_io_error.hpp"
#include "deformation_enrichment/mesh/gmsh_io.hpp"
#include "deformation_enrichment/mesh/grid_tet_mesh.hpp"
#include "deformation_enrichment/mesh/volume_mesh_io.hpp"
#include "deformation_enrichment/mesh/vtk_io.hpp"

using namespace deformation_enrichment;

namespace {

/// A temporary folder for one test, removed with it.
class VolumeMeshIo : public ::testing::Test {
protected:
  void SetUp() override {
    dir_ = ::testing::TempDir() + "de_volume_io_" + std::to_string(::getpid()) + "_" +
           ::testing::UnitTest::GetInstance()->current_test_info()->name() + "/";
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string path(const std::string& name) const { return dir_ + name; }
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(path(name), std::ios::binary) << text;
    return path(name);
  }
  /// Runs Debian's gmsh executable on a .geo file; false when gmsh is not installed.
  bool gmsh(const std::string& geo, const std::string& arguments, const std::string& output) const {
    if (std::system("command -v gmsh > /dev/null") != 0) return false;
    const std::string command = "gmsh -3 " + path(geo) + " " + arguments + " -o " + path(output) + " > /dev/null 2>&1";
    return std::system(command.c_str()) == 0;
  }
  std::string dir_;
};

// Two unit boxes sharing a face, physical volumes 7 and 9 (OpenCASCADE kernel of Debian's gmsh).
const char* kTwoBoxes =
    "SetFactory(\"OpenCASCADE\");\nBox(1) = {0, 0, 0, 1, 1, 1};\nBox(2) = {1, 0, 0, 1, 1, 1};\nCoherence;\n"
    "Physical Volume(7) = {1};\nPhysical Volume(9) = {2};\nPhysical Surface(3) = {1};\n"
    "Mesh.CharacteristicLengthMax = 0.5;\n";

mesh::VolumeMeshFile readMsh(const std::string& text) {
  std::istringstream in(text, std::ios::binary);
  return mesh::readGmsh(in, "test.msh");
}

}  // namespace

TEST_F(VolumeMeshIo, GmshFilesOfEveryVersionAndEncodingAgree) {
  write("boxes.geo", kTwoBoxes);
  const std::vector<std::pair<std::string, std::string>> variants = {
      {"msh22", "-format msh22"}, {"msh22b", "-format msh22 -bin"}, {"msh41", "-format msh41"},
      {"msh41b", "-format msh41 -bin"}, {"order2", "-order 2 -format msh41 -bin"}, {"msh1", "-format msh1"}};
  if (!gmsh("boxes.geo", variants[0].second, "msh22.msh")) DE_MISSING_INPUT("Debian's gmsh is not installed");
  const mesh::VolumeMeshFile first = mesh::readVolumeMesh(path("msh22.msh"));
  EXPECT_NEAR(mesh::totalVolume(first.mesh), 2.0, 1e-12);
  EXPECT_EQ(first.report.reorientedTets, 0);  // gmsh writes positively oriented tets
  EXPECT_EQ(first.report.unusedNodes, 0);
  EXPECT_GT(first.report.skippedCells.at("triangle"), 0);  // the physical surface
  EXPECT_EQ(first.report.skippedCells.size(), 1u);
  const long inBox7 = (first.region.array() == 7).count(), inBox9 = (first.region.array() == 9).count();
  EXPECT_EQ(inBox7 + inBox9, first.mesh.numTets());
  EXPECT_GT(inBox7, 0);
  EXPECT_GT(inBox9, 0);
  for (Eigen::Index t = 0; t < first.mesh.numTets(); ++t) {  // region 7 is the box x < 1
    const double x = first.mesh.vertices(0, first.mesh.tets.col(t)).mean();
    EXPECT_EQ(first.region[t], x < 1.0 ? 7 : 9);
  }
  for (const auto& [name, arguments] : variants) {
    ASSERT_TRUE(gmsh("boxes.geo", arguments, name + ".msh")) << arguments;
    const mesh::VolumeMeshFile read = mesh::readVolumeMesh(path(name + ".msh"));
    EXPECT_EQ(read.region, first.region) << name;
    EXPECT_EQ(read.report.skippedCells, first.report.skippedCells) << name;
    ASSERT_EQ(read.mesh.numTets(), first.mesh.numTets()) << name;
    if (name == "order2") {
      // Second order adds mid-edge nodes (gmsh renumbers them among the corners): they are in no tet.
      EXPECT_EQ(read.report.unusedNodes, read.mesh.numVertices() - first.mesh.numVertices());
      for (Eigen::Index t = 0; t < read.mesh.numTets(); ++t)
        for (int k = 0; k < 4; ++k)
          EXPECT_LT((read.mesh.vertices.col(read.mesh.tets(k, t)) - first.mesh.vertices.col(first.mesh.tets(k, t))).norm(), 1e-15);
      continue;
    }
    EXPECT_EQ(read.mesh.tets, first.mesh.tets) << name;
    EXPECT_LT((read.mesh.vertices - first.mesh.vertices).cwiseAbs().maxCoeff(), 1e-15) << name;
    EXPECT_EQ(read.nodeIds, first.nodeIds) << name;
  }
  EXPECT_EQ(first.nodeIds.front(), 1);  // gmsh numbers nodes from 1; indices are 0-based file order
}

TEST_F(VolumeMeshIo, GmshVtkExportReadThroughVtkMatchesItsMsh) {
  write("boxes.geo", kTwoBoxes);
  if (!gmsh("boxes.geo", "-format msh41", "boxes.msh")) DE_MISSING_INPUT("Debian's gmsh is not installed");
  ASSERT_TRUE(gmsh("boxes.geo", "-format vtk", "boxes.vtk"));  // legacy ASCII 2.0, mixed cells
  const mesh::VolumeMeshFile msh = mesh::readVolumeMesh(path("boxes.msh"));
  const mesh::VolumeMeshFile vtk = mesh::readVolumeMesh(path("boxes.vtk"));
  EXPECT_EQ(vtk.mesh.tets, msh.mesh.tets);
  EXPECT_LT((vtk.mesh.vertices - msh.mesh.vertices).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_EQ(vtk.report.skippedCells.at("triangle"), msh.report.skippedCells.at("triangle"));
  EXPECT_EQ(vtk.nodeIds.front(), 0);
}

TEST_F(VolumeMeshIo, GmshInvertedTetsAreReorderedAndBadFilesNamed) {
  const std::string nodes = "$Nodes\n5\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n9 1 1 1\n$EndNodes\n";
  const std::string header = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n";
  // Element 2 is inverted; 3 is a triangle; a comment section is skipped.
  const mesh::VolumeMeshFile read = readMsh(header + "$Comments\nanything\n$EndComments\n" + nodes +
                                            "$Elements\n3\n1 4 2 5 1 1 2 3 4\n2 4 0 3 2 4 9\n3 2 0 1 2 3\n$EndElements\n");
  EXPECT_EQ(read.report.reorientedTets, 1);
  EXPECT_EQ(read.report.skippedCells.at("triangle"), 1);
  EXPECT_EQ(read.region, Eigen::Vector2i(5, 0));
  EXPECT_NO_THROW(mesh::validate(read.mesh));
  EXPECT_EQ(read.nodeIds.back(), 9);
  const std::string elements = "$Elements\n1\n1 4 0 1 2 3 4\n$EndElements\n";
  test::expectIoError([&] { readMsh(header + nodes + "$Elements\n1\n1 4 0 1 2 3 8\n$EndElements\n"); },
                {"test.msh:14:", "node tag 8"});
  test::expectIoError([&] { readMsh(header + "$Nodes\n1\n1 0 x 0\n$EndNodes\n" + elements); }, {"test.msh:6:", "'x'"});
  test::expectIoError([&] { readMsh(header + nodes + "$Elements\n1\n1 99 0 1\n$EndElements\n"); }, {":14:", "type 99"});
  test::expectIoError([&] { readMsh(header + nodes + "$Elements\n1\n1 4 0 1 2 2 4\n$EndElements\n"); }, {":14:", "repeated"});
  test::expectIoError([&] { readMsh(header + nodes + "$Elements\n1\n1 4 0 1 2 3 5\n$EndElements\n"); }, {":14:", "node tag 5"});
  test::expectIoError([&] { readMsh("$MeshFormat\n4 0 8\n$EndMeshFormat\n"); }, {"test.msh:2:", "version 4"});
  test::expectIoError([&] { readMsh(header + nodes); }, {"no $Elements"});
  test::expectIoError([&] { readMsh(header + nodes + "$Elements\n2\n1 4 0 1 2 3 4\n"); }, {"test.msh", "ends"});
  test::expectIoError([&] { readMsh(header + nodes + "$Elements\n1\n1 2 0 1 2 3\n$EndElements\n"); }, {"no tetrahedra"});
  test::expectIoError([&] { readMsh(header + "$Junk\n"); }, {"$Junk has no $EndJunk"});
  test::expectIoError([&] { mesh::readGmsh(path("missing.msh")); }, {"missing.msh"});
}

// MSH 1.0, as SOFA's meshes (liver.msh) are written: no $MeshFormat, $NOD / $ELM with two region tags.
TEST_F(VolumeMeshIo, GmshVersion1IsReadAndBadFilesNamed) {
  const std::string nodes = "$NOD\n5\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n9 1 1 1\n$ENDNOD\n";
  const mesh::VolumeMeshFile read = readMsh(nodes + "$ELM\n3\n1 4 5 1 4 1 2 3 4\n2 4 0 1 4 3 2 4 9\n3 2 0 1 3 1 2 3\n$ENDELM\n");
  EXPECT_EQ(read.mesh.numTets(), 2);
  EXPECT_EQ(read.report.reorientedTets, 1);
  EXPECT_EQ(read.report.skippedCells.at("triangle"), 1);
  EXPECT_EQ(read.region, Eigen::Vector2i(5, 0));
  EXPECT_NO_THROW(mesh::validate(read.mesh));
  test::expectIoError([&] { readMsh(nodes + "$ELM\n1\n1 4 0 1 3 1 2 3\n$ENDELM\n"); }, {"node count does not match"});
  test::expectIoError([&] { readMsh(nodes + "$ELM\n1\n1 4 0 1 4 1 2 3 4\n$ENDELM\nextra\n"); }, {"after $ENDELM"});
  test::expectIoError([&] { readMsh(nodes + "$ELM\n1\n1 4 0 1 4 1 2 3 7\n$ENDELM\n"); }, {"node tag 7"});
  test::expectIoError([&] { readMsh("$NOD\n1\n1 0 0\n"); }, {"test.msh"});
  test::expectIoError([&] { readMsh("$Nodes\n1\n"); }, {"expected $MeshFormat"});
}

TEST_F(VolumeMeshIo, TruncatedBinaryGmshNamesTheByte) {
  write("boxes.geo", kTwoBoxes);
  if (!gmsh("boxes.geo", "-format msh41 -bin", "boxes.msh")) DE_MISSING_INPUT("Debian's gmsh is not installed");
  std::ifstream in(path("boxes.msh"), std::ios::binary);
  std::string bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  bytes.resize(bytes.size() * 2 / 3);  // inside the binary $Nodes or $Elements data
  test::expectIoError([&] { readMsh(bytes); }, {"test.msh: byte ", "file ends inside"});
}

TEST_F(VolumeMeshIo, VtkWritersOutputReadsBackExactly) {
  Eigen::VectorXd xs(3), ys(2), zs(3);
  xs << -0.1, 0.013, 0.2;
  ys << 0.0, 0.1;
  zs << 0.3, 0.31, 0.37;
  const mesh::TetMesh grid = mesh::gridTetMesh(xs, ys, zs);
  for (const std::string name : {"grid.vtk", "grid.vtu"}) {  // legacy binary 5.1; XML appended, zlib
    mesh::writeVtk(path(name), grid);
    const mesh::VolumeMeshFile read = mesh::readVolumeMesh(path(name));
    EXPECT_EQ(read.mesh.tets, grid.tets) << name;
    EXPECT_EQ((read.mesh.vertices - grid.vertices).cwiseAbs().maxCoeff(), 0.0) << name;  // doubles
    EXPECT_TRUE(read.report.skippedCells.empty()) << name;
  }
  EXPECT_THROW(mesh::writeVtk(path("grid.obj"), grid), IoError);
  EXPECT_THROW(mesh::writeVtk("/nonexistent_dir/grid.vtu", grid), IoError);
}

TEST_F(VolumeMeshIo, VtkXmlAsciiWithAHexAndAnInvertedTet) {
  // Points 0-3 a unit tet listed inverted (0 2 1 3), 4-11 a hexahedron; ASCII data, offsets, types.
  const std::string vtu =
      "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
      "<UnstructuredGrid><Piece NumberOfPoints=\"12\" NumberOfCells=\"2\">\n"
      "<Points><DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n"
      "0 0 0 1 0 0 0 1 0 0 0 1  2 0 0 3 0 0 3 1 0 2 1 0 2 0 1 3 0 1 3 1 1 2 1 1\n</DataArray></Points>\n"
      "<Cells><DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">0 2 1 3 4 5 6 7 8 9 10 11</DataArray>\n"
      "<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">4 12</DataArray>\n"
      "<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">10 12</DataArray></Cells>\n"
      "</Piece></UnstructuredGrid></VTKFile>\n";
  const mesh::VolumeMeshFile read = mesh::readVolumeMesh(write("mixed.vtu", vtu));
  EXPECT_EQ(read.mesh.numTets(), 1);
  EXPECT_EQ(read.report.reorientedTets, 1);
  EXPECT_EQ(read.report.skippedCells.at("hexahedron"), 1);
  EXPECT_EQ(read.report.unusedNodes, 8);
  EXPECT_NEAR(mesh::signedVolume(read.mesh, 0), 1.0 / 6.0, 1e-15);
}

TEST_F(VolumeMeshIo, CorruptVtkFilesNameFileAndProblem) {
  const std::string legacy = "# vtk DataFile Version 2.0\nx\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 4 double\n";
  const auto readLegacy = [](const std::string& text) {
    return [text] {
      std::istringstream in(text);
      mesh::readVtk(in, false, "bad.vtk");
    };
  };
  test::expectIoError(readLegacy(legacy + "0 0 0 1 0 0 0 1 0\n"), {"bad.vtk", "POINTS", "12 values declared"});  // 3 of 4 points
  // Found by fuzz_vtk in VTK 9.1's legacy reader (reads past CELLS, null dereference on a missing size).
  const std::string points = legacy + "0 0 0 1 0 0 0 1 0 0 0 1\n";
  test::expectIoError(readLegacy(points + "CELLS 1 5\n46841 0 1 2 3\nCELL_TYPES 1\n10\n"), {"bad.vtk", "cell 0 declares 46841 points"});
  test::expectIoError(readLegacy(points + "CELLS 1\n0.5 0 1 2 3\n"), {"bad.vtk", "CELLS", "not a count", "line 8"});
  test::expectIoError(readLegacy(points + "CELLS 1 5\n4 0 1 2 3\nCELL_TYPES 2\n10\n10\n"), {"bad.vtk", "1 CELLS but 2 CELL_TYPES"});
  test::expectIoError(readLegacy(legacy.substr(0, legacy.size() - 16) + "POINTS 99999999 double\n0 0 0\n"), {"bad.vtk", "more than the rest"});
  test::expectIoError(readLegacy(legacy + "0 0 0 1 0 0 0 1 0 0 0 1\nCELLS 1 5\n4 0 1 2 9\nCELL_TYPES 1\n10\n"),
                {"bad.vtk: cell 0:", "out of range"});
  test::expectIoError(readLegacy("# vtk DataFile Version 2.0\nx\nASCII\nDATASET POLYDATA\nPOINTS 1 double\n0 0 0\n"),
                {"bad.vtk", "polydata"});
  test::expectIoError(readLegacy("garbage"), {"bad.vtk"});
  test::expectIoError(readLegacy(""), {"bad.vtk", "empty"});
  std::istringstream xml("<VTKFile type=\"UnstructuredGrid\"><Unstru");
  test::expectIoError([&] { mesh::readVtk(xml, true, "bad.vtu"); }, {"bad.vtu", "line 1, column"});
  test::expectIoError([&] { mesh::readVolumeMesh(path("missing.vtu")); }, {"missing.vtu"});
}

TEST_F(VolumeMeshIo, DispatchByExtension) {
  const std::string tetgen = std::string(DE_SOURCE_DIR) + "/test/data/tetgen/box.1";
  for (const std::string ext : {".node", ".ele"}) {
    const mesh::VolumeMeshFile read = mesh::readVolumeMesh(tetgen + ext);
    EXPECT_EQ(read.mesh.numTets(), 80);
    EXPECT_EQ(read.nodeIds.front(), 1);  // the files number points from 1
    EXPECT_NE(mesh::describe(read).find("46 nodes, 80 tets"), std::string::npos) << mesh::describe(read);
  }
  EXPECT_EQ(mesh::volumeFormatOf("A.MSH"), mesh::VolumeFormat::Gmsh);
  EXPECT_EQ(mesh::volumeFormatOf("a.vtu"), mesh::VolumeFormat::VtkXml);
  test::expectIoError([] { mesh::readVolumeMesh("liver.obj"); }, {"liver.obj", "unsupported extension"});
}
