// The CalculiX check: the deck ccx reads, the .dat displacements it writes, the errors of a run that goes
// wrong, the CalculiX neo-Hookean's stress, and a real ccx run that must match our SNH solver at small strain.
// Without ccx the real runs fail under CI=true (scripts/install-deps installs calculix-ccx) and skip otherwise.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <unistd.h>
#include <vector>

#include "../expect_error.hpp"
#include "../missing_input.hpp"
#include "deformation_enrichment/elasticity/calculix_comparison.hpp"
#include "deformation_enrichment/elasticity/calculix_dat.hpp"
#include "deformation_enrichment/elasticity/calculix_deck.hpp"
#include "deformation_enrichment/elasticity/calculix_run.hpp"
#include "deformation_enrichment/elasticity/compressible_neo_hookean.hpp"
#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/grid_tet_mesh.hpp"
#include "deformation_enrichment/root_mean_square.hpp"

using namespace deformation_enrichment;
using namespace deformation_enrichment::elasticity;

namespace {

bool onPath(const std::string& program) {
  const char* path = std::getenv("PATH");
  std::stringstream folders(path ? path : "");
  for (std::string folder; std::getline(folders, folder, ':');)
    if (!folder.empty() && ::access((std::filesystem::path(folder) / program).c_str(), X_OK) == 0) return true;
  return false;
}

// Real ccx runs: a missing ccx fails the test under CI=true and skips it elsewhere.
#define REQUIRE_CCX() \
  if (!onPath("ccx")) DE_MISSING_INPUT("ccx is not installed (Debian package calculix-ccx)")

// Two positively oriented tets sharing the face 1-2-3: (0,1,2,3) and (1,2,3,4), one per material;
// vertex 0 fixed, vertex 4 pushed down by 0.1.
CalculixModel twoTets() {
  CalculixModel model;
  model.rest.vertices.resize(3, 5);
  model.rest.vertices << 0, 1, 0, 0, 1,  //
      0, 0, 1, 0, 1,                     //
      0, 0, 0, 1, 1;
  model.rest.tets.resize(4, 2);
  model.rest.tets << 0, 1, 1, 2, 2, 3, 3, 4;
  model.materials = {{3.0, 0.25}, {6.0, 0.25}};  // (mu, kappa) = (1.2, 2) and (2.4, 4)
  model.materialId = (Eigen::VectorXi(2) << 0, 1).finished();
  model.constraints.add(0, model.rest.vertices.col(0));
  model.constraints.add(4, model.rest.vertices.col(4) + Eigen::Vector3d(0, 0, -0.1));
  return model;
}

std::vector<std::string> deckLines(const CalculixModel& model) {
  std::ostringstream out;
  writeCalculixDeck(out, model);
  std::vector<std::string> lines;
  std::istringstream in(out.str());
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

/// Expects `expected` as consecutive lines of `lines`, starting at the first line equal to expected[0].
void expectBlock(const std::vector<std::string>& lines, const std::vector<std::string>& expected) {
  const auto start = std::find(lines.begin(), lines.end(), expected.front());
  ASSERT_NE(start, lines.end()) << "no line '" << expected.front() << "'";
  for (std::size_t k = 0; k < expected.size(); ++k) {
    ASSERT_LT(static_cast<std::size_t>(start - lines.begin()) + k, lines.size()) << "deck ends before " << expected[k];
    EXPECT_EQ(*(start + static_cast<std::ptrdiff_t>(k)), expected[k]);
  }
}

/// An executable shell script in the test's temporary folder (a stand-in for ccx).
std::string script(const std::string& name, const std::string& body) {
  const std::string path = testing::TempDir() + name + "_" + std::to_string(::getpid()) + ".sh";
  std::ofstream(path) << "#!/bin/sh\n" << body;
  std::filesystem::permissions(path, std::filesystem::perms::owner_all);
  return path;
}

// A 2 x 2 x 1 cm block on 4 x 4 x 2 cells, a stiff top layer (E = 1e5) over soft bulk (E = 1e4), the
// bottom held and the top centre pushed down by `depth`.
CalculixModel block(double depth) {
  CalculixModel model;
  model.rest = mesh::gridTetMesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0.02, 0.02, 0.01), Eigen::Vector3i(4, 4, 2));
  model.materials = {{1e4, 0.45}, {1e5, 0.3}};
  model.materialId.resize(model.rest.numTets());
  for (Eigen::Index t = 0; t < model.rest.numTets(); ++t) {
    double z = 0.0;
    for (int c = 0; c < 4; ++c) z += 0.25 * model.rest.vertices(2, model.rest.tets(c, t));
    model.materialId[t] = z > 0.005 ? 1 : 0;
  }
  for (Eigen::Index v = 0; v < model.rest.numVertices(); ++v) {
    const Eigen::Vector3d X = model.rest.vertices.col(v);
    if (X.z() == 0.0) model.constraints.add(static_cast<int>(v), X);
    if ((X - Eigen::Vector3d(0.01, 0.01, 0.01)).norm() < 1e-9)
      model.constraints.add(static_cast<int>(v), X - Eigen::Vector3d(0, 0, depth));
  }
  return model;
}

}  // namespace

TEST(CalculixDeck, NeoHookeConstantsUseThePhysicalBulkModulus) {
  // E = 3, nu = 1/4: mu = lambda = 1.2, kappa = lambda + 2/3 mu = 2, so C10 = mu/2 = 0.6, D1 = 2/kappa = 1.
  const NeoHookeConstants nh = neoHookeConstants({3.0, 0.25});
  EXPECT_NEAR(nh.c10, 0.6, 1e-15);
  EXPECT_NEAR(nh.d1, 1.0, 1e-15);
  expectErrorContaining<InvalidInputError>([] { neoHookeConstants({1.0, 0.5}); }, "Poisson");
}

TEST(CalculixDeck, TwoTetsGiveNodesElementSetsMaterialsAndBoundary) {
  const std::vector<std::string> lines = deckLines(twoTets());
  expectBlock(lines, {"*NODE, NSET=Nall", "1, 0, 0, 0", "2, 1, 0, 0", "3, 0, 1, 0", "4, 0, 0, 1", "5, 1, 1, 1"});
  // Tets keep their order (the TetMesh orientation is C3D4's), numbered from 1, one set per material.
  expectBlock(lines, {"*ELEMENT, TYPE=C3D4, ELSET=M0", "1, 1, 2, 3, 4", "*MATERIAL, NAME=M0", "*HYPERELASTIC, NEO HOOKE",
                      "0.6, 1", "*SOLID SECTION, ELSET=M0, MATERIAL=M0"});
  expectBlock(lines, {"*ELEMENT, TYPE=C3D4, ELSET=M1", "2, 2, 3, 4, 5", "*MATERIAL, NAME=M1", "*HYPERELASTIC, NEO HOOKE",
                      "1.2, 0.5", "*SOLID SECTION, ELSET=M1, MATERIAL=M1"});
  expectBlock(lines, {"*STEP, NLGEOM, INC=4000", "*STATIC", "0.25, 1.0, 2.5e-07, 0.25", "*CONTROLS, PARAMETERS=FIELD",
                      "1e-08, 1e-08", "*BOUNDARY", "1, 1, 3, 0", "5, 1, 1, 0", "5, 2, 2, 0", "5, 3, 3, -0.1",
                      "*NODE PRINT, NSET=Nall", "U", "*END STEP"});
}

TEST(CalculixDeck, UnusedMaterialGetsNoEmptyElementSet) {
  CalculixModel model = twoTets();
  model.materialId = Eigen::VectorXi::Ones(2);
  const std::vector<std::string> lines = deckLines(model);
  EXPECT_EQ(std::count(lines.begin(), lines.end(), "*ELEMENT, TYPE=C3D4, ELSET=M0"), 0);
  expectBlock(lines, {"*ELEMENT, TYPE=C3D4, ELSET=M1", "1, 1, 2, 3, 4", "2, 2, 3, 4, 5"});
}

TEST(CalculixDeck, RejectsInvalidModels) {
  std::ostringstream out;
  CalculixModel inverted = twoTets();
  std::swap(inverted.rest.tets(1, 0), inverted.rest.tets(2, 0));  // ccx would report a nonpositive jacobian
  EXPECT_THROW(writeCalculixDeck(out, inverted), InvalidInputError);
  CalculixModel badId = twoTets();
  badId.materialId[1] = 2;
  expectErrorContaining<InvalidInputError>([&] { writeCalculixDeck(out, badId); }, "material id");
  CalculixModel twice = twoTets();
  twice.constraints.add(4, twice.rest.vertices.col(4));
  expectErrorContaining<InvalidInputError>([&] { writeCalculixDeck(out, twice); }, "constrained twice");
  CalculixModel noSteps = twoTets();
  noSteps.increments = 0;
  expectErrorContaining<InvalidInputError>([&] { writeCalculixDeck(out, noSteps); }, "increments");
}

TEST(CalculixDat, ReadsTheLastBlock) {
  std::istringstream dat(
      "\n displacements (vx,vy,vz) for set NALL and time  0.5000000E+00\n\n"
      "         1  0.000000E+00  0.000000E+00  0.000000E+00\n"
      "         2 -1.000000E-03  0.000000E+00  5.000000E-03\n\n"
      " displacements (vx,vy,vz) for set NALL and time  0.1000000E+01\n\n"
      "         2 -2.249508E-03  1.000000E-99  1.000000E-02\n"
      "         1  0.000000E+00  0.123457-100 -3.000000E+00\n");
  const CalculixDisplacements u = readCalculixDisplacements(dat, 2, "job.dat");
  EXPECT_DOUBLE_EQ(u.time, 1.0);
  EXPECT_DOUBLE_EQ(u.values(0, 1), -2.249508e-3);
  EXPECT_DOUBLE_EQ(u.values(1, 1), 1e-99);
  EXPECT_DOUBLE_EQ(u.values(2, 1), 1e-2);
  EXPECT_DOUBLE_EQ(u.values(1, 0), 0.123457e-100);  // Fortran drops the E of a three-digit exponent
  EXPECT_DOUBLE_EQ(u.values(2, 0), -3.0);
}

TEST(CalculixDat, NamesTheProblem) {
  const auto read = [](const std::string& text, Eigen::Index nodes) {
    std::istringstream in(text);
    readCalculixDisplacements(in, nodes, "job.dat");
  };
  const std::string header = " displacements (vx,vy,vz) for set NALL and time  0.1000000E+01\n";
  expectErrorContaining<IoError>([&] { read(" Job finished\n", 1); }, "job.dat: no displacement block");
  expectErrorContaining<IoError>([&] { read(header + " 1 0 0 0\n", 2); }, "lists 1 of 2 nodes");
  expectErrorContaining<IoError>([&] { read(header + " 1 0 0 0\n 1 0 0 0\n", 2); }, "job.dat:3: node 1 listed twice");
  expectErrorContaining<IoError>([&] { read(header + " 3 0 0 0\n", 2); }, "node 3 outside 1..2");
  expectErrorContaining<IoError>([&] { read(header + " 1 0 x 0\n", 1); }, "bad displacement 'x'");
  expectErrorContaining<IoError>([&] { read(header + " 1 0 0\n", 1); }, "expected 'node ux uy uz'");
}

TEST(CalculixRun, ReportsWhyARunFailed) {
  const CalculixModel model = twoTets();
  CalculixOptions options;
  options.program = "de_no_such_ccx";
  expectErrorContaining<IoError>([&] { runCalculix(model, options); }, "cannot run 'de_no_such_ccx'");
  options.program = script("ccx_fails", "echo ' *ERROR in e_c3d: nonpositive jacobian'\nexit 201\n");
  expectErrorContaining<IoError>([&] { runCalculix(model, options); }, "(exit code 201): *ERROR in e_c3d: nonpositive jacobian");
  // ccx exits 0 after some rejected decks; its *ERROR line still counts.
  options.program = script("ccx_rejects", "echo ' *ERROR in readinput: cannot open file job.inp'\n");
  expectErrorContaining<IoError>([&] { runCalculix(model, options); }, "rejected");
  options.program = script("ccx_silent", "test -f job.inp\n");
  expectErrorContaining<IoError>([&] { runCalculix(model, options); }, "job.dat");
  std::string block = "printf ' displacements (vx,vy,vz) for set NALL and time  0.5000000E+00\\n\\n";
  for (int node = 1; node <= 5; ++node) block += " " + std::to_string(node) + " 0 0 0\\n";
  options.program = script("ccx_stops", block + "' > job.dat\n");
  expectErrorContaining<IoError>([&] { runCalculix(model, options); }, "stopped at step time 0.5");
  for (const char* name : {"ccx_fails", "ccx_rejects", "ccx_silent", "ccx_stops"})
    std::filesystem::remove(testing::TempDir() + name + "_" + std::to_string(::getpid()) + ".sh");
}

TEST(CompressibleNeoHookean, StressIsTheEnergyGradient) {
  const CompressibleNeoHookean material(1.5, 7.0);
  Eigen::Matrix3d F;
  F << 1.1, 0.2, -0.1, 0.05, 0.9, 0.15, -0.2, 0.1, 1.2;
  const Eigen::Matrix3d P = material.pk1(F);
  const double h = 1e-6;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) {
      Eigen::Matrix3d plus = F, minus = F;
      plus(r, c) += h;
      minus(r, c) -= h;
      EXPECT_NEAR(P(r, c), (material.psi(plus) - material.psi(minus)) / (2 * h), 1e-7) << r << ", " << c;
    }
  EXPECT_NEAR(material.psi(Eigen::Matrix3d::Identity()), 0.0, 1e-15);
  EXPECT_LT(material.pk1(Eigen::Matrix3d::Identity()).norm(), 1e-15);
  EXPECT_THROW(material.psi(-Eigen::Matrix3d::Identity()), InvalidInputError);
}

TEST(CalculixRun, MatchesOurSolverAtSmallStrain) {
  REQUIRE_CCX();
  const CalculixModel model = block(2e-5);
  const CalculixComparison c = compareWithCalculix(model);
  EXPECT_LT(c.maxGreenStrain, 0.01);
  EXPECT_GT(c.maxGreenStrain, 1e-4);  // a real load, not a rounding-level one
  EXPECT_LT(c.relativeDifference, 0.01) << "rms " << c.rmsDisplacement;
  // ccx holds the prescribed displacements (printed to 7 digits).
  for (std::size_t k = 0; k < model.constraints.vertices.size(); ++k) {
    const int v = model.constraints.vertices[k];
    const Eigen::Vector3d u = model.constraints.positions.col(static_cast<Eigen::Index>(k)) - model.rest.vertices.col(v);
    EXPECT_LT((c.calculixDisplacements.col(v) - u).norm(), 1e-6 * 2e-5 + 1e-15) << "vertex " << v;
  }
  // Its answer is an equilibrium of its own energy: the neo-Hookean force left at u_ccx is small beside
  // the force the energy forms differ by.
  EXPECT_LT(c.calculixResidualRatio, 0.1);
}

TEST(CalculixRun, MaterialsPerElementSetMatter) {
  REQUIRE_CCX();
  const CalculixModel model = block(2e-5);
  CalculixModel swapped = model;
  swapped.materialId = 1 - model.materialId.array();
  const CalculixComparison c = compareWithCalculix(model);
  const Eigen::Matrix3Xd other = runCalculix(swapped).displacements;
  // Stiff skin and soft bulk exchanged: far beyond the 1 % the matching model stays within.
  EXPECT_GT(rootMeanSquare(other - c.ourDisplacements) / c.rmsDisplacement, 0.05);
}
