// The Discrete Shells energy values against an independent numpy implementation of the papers' formulas
// (test/oracle/discrete_shells_energy.py): explicit fundamental forms, arccos angles, cross-product areas.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <iomanip>
#include <string>

#include "deformation_enrichment/shape_space/discrete_shells.hpp"
#include "shell_test_meshes.hpp"

namespace deformation_enrichment::shape_space {
namespace {

double oracleEnergy(const DiscreteShellsOptions& p, const Eigen::Matrix3Xi& triangles, const Eigen::VectorXd& reference,
                    const Eigen::VectorXd& deformed) {
  const std::string path = ::testing::TempDir() + "discrete_shells_oracle_input.txt";
  {
    std::ofstream out(path);
    out << std::setprecision(17) << (p.membrane == MembraneModel::DiscreteShells ? "classic" : "hyperelastic") << ' '
        << reference.size() / 3 << ' ' << triangles.cols() << ' ' << p.lengthWeight << ' ' << p.areaWeight << ' '
        << p.mu << ' ' << p.lambda << ' ' << p.bendingWeight << '\n';
    for (const Eigen::VectorXd* shape : {&reference, &deformed}) {
      for (Eigen::Index v = 0; v < shape->size() / 3; ++v) {
        out << (*shape)[3 * v] << ' ' << (*shape)[3 * v + 1] << ' ' << (*shape)[3 * v + 2] << '\n';
      }
    }
    out << triangles.transpose() << '\n';
  }
  const std::string command = "/usr/bin/python3 " DE_SOURCE_DIR "/test/oracle/discrete_shells_energy.py " + path;
  FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) return std::nan("");
  char buffer[128] = {0};
  const bool read = std::fgets(buffer, sizeof(buffer), pipe) != nullptr;
  const int status = pclose(pipe);
  return (read && status == 0) ? std::stod(buffer) : std::nan("");
}

TEST(DiscreteShellsOracle, ValuesMatchAnIndependentNumpyImplementation) {
  DiscreteShellsOptions hyperelastic = DiscreteShellsOptions::hyperelastic(0.05);
  hyperelastic.mu = 1.3;
  hyperelastic.lambda = 0.7;
  DiscreteShellsOptions classic = DiscreteShellsOptions::classic();
  classic.lengthWeight = 0.4;
  for (const auto& parameters : {hyperelastic, classic}) {
    for (const test::FlatMesh& mesh : {test::bumpyGrid(5, 21), test::octahedron()}) {
      const DiscreteShells energy(mesh.triangles, mesh.vertices.size() / 3, parameters);
      const Eigen::VectorXd deformed = test::perturbed(mesh.vertices, 0.1, 4);
      const double ours = energy.value(mesh.vertices, deformed);
      const double oracle = oracleEnergy(parameters, mesh.triangles, mesh.vertices, deformed);
      ASSERT_TRUE(std::isfinite(oracle)) << "the numpy oracle did not run";
      EXPECT_NEAR(ours, oracle, 1e-10 * std::abs(oracle)) << "membrane model " << static_cast<int>(parameters.membrane);
      EXPECT_GT(energy.bendingValue(mesh.vertices, deformed), 1e-3 * ours);  // bending matters in the comparison
    }
  }
}

}  // namespace
}  // namespace deformation_enrichment::shape_space
