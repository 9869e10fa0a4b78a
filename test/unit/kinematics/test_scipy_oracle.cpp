// Polar decomposition and Kabsch against SciPy (scipy.linalg.polar, Rotation.align_vectors), run as an
// independent oracle through test/oracle/kinematics_oracle.py with /usr/bin/python3.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "deformation_enrichment/kinematics/kabsch.hpp"
#include "deformation_enrichment/kinematics/polar_decomposition.hpp"

using namespace deformation_enrichment;
using nlohmann::json;

namespace {

std::vector<double> colMajor(const Eigen::MatrixXd& m) { return {m.data(), m.data() + m.size()}; }

Eigen::MatrixXd fromJson(const json& values, Eigen::Index rows) {
  const std::vector<double> v = values.get<std::vector<double>>();
  return Eigen::Map<const Eigen::MatrixXd>(v.data(), rows, static_cast<Eigen::Index>(v.size()) / rows);
}

Eigen::Matrix3d randomRotation() {
  return Eigen::Quaterniond(Eigen::Vector4d::Random()).normalized().toRotationMatrix();
}

// Runs the SciPy oracle on a request and returns its answer; fails the test if python cannot run it.
json runOracle(const json& request, const std::string& name) {
  const std::string in = testing::TempDir() + "kinematics_oracle_" + name + "_in.json";
  const std::string out = testing::TempDir() + "kinematics_oracle_" + name + "_out.json";
  std::ofstream(in) << request.dump();
  const std::string command = std::string("/usr/bin/python3 ") + DE_SOURCE_DIR +
                              "/test/oracle/kinematics_oracle.py " + in + " " + out;
  const int status = std::system(command.c_str());
  EXPECT_EQ(status, 0) << "oracle failed: " << command;
  std::ifstream answer(out);
  EXPECT_TRUE(answer.good()) << "oracle wrote no answer";
  return status == 0 && answer.good() ? json::parse(answer) : json::object();
}

struct PolarCase {
  std::string label;
  Eigen::Matrix3d F;
};

// F = Q diag(sigma) Vᵀ with random rotations Q, V: controls singular values and sign of det F.
Eigen::Matrix3d withSingularValues(const Eigen::Vector3d& sigma) {
  return randomRotation() * sigma.asDiagonal() * randomRotation().transpose();
}

}  // namespace

TEST(ScipyOracle, PolarDecompositionMatchesScipyIncludingInvertedAndNearSingular) {
  std::srand(42);
  std::vector<PolarCase> cases;
  for (int k = 0; k < 10; ++k) cases.push_back({"random " + std::to_string(k), Eigen::Matrix3d::Random()});
  cases.push_back({"near identity", Eigen::Matrix3d::Identity() + 1e-3 * Eigen::Matrix3d::Random()});
  cases.push_back({"inverted", withSingularValues({1.5, 1.0, -0.5})});
  cases.push_back({"reflection x rotation", withSingularValues({1.0, 0.9, -0.8})});
  cases.push_back({"near-singular", withSingularValues({2.0, 1.0, 1e-9})});
  cases.push_back({"near-singular inverted", withSingularValues({2.0, 1.0, -1e-9})});
  cases.push_back({"rank 2", withSingularValues({2.0, 0.5, 0.0})});
  cases.push_back({"large scale", 1e6 * withSingularValues({3.0, 2.0, 1.0})});
  cases.push_back({"tiny scale", 1e-6 * withSingularValues({3.0, 2.0, -1.0})});

  json request;
  request["polar"] = json::array();
  for (const auto& c : cases) request["polar"].push_back(colMajor(c.F));
  const json answer = runOracle(request, "polar");
  ASSERT_EQ(answer.value("polar", json::array()).size(), cases.size());

  for (size_t k = 0; k < cases.size(); ++k) {
    SCOPED_TRACE(cases[k].label);
    const Eigen::Matrix3d& F = cases[k].F;
    const auto pd = kinematics::polarDecomposition(F);
    const Eigen::Matrix3d R = fromJson(answer["polar"][k]["R"], 3);
    const Eigen::Matrix3d S = fromJson(answer["polar"][k]["S"], 3);
    // What is unique for every F, whatever the rank: a proper rotation, R S = F, S symmetric.
    EXPECT_NEAR(pd.R.determinant(), 1.0, 1e-12);
    EXPECT_LT((pd.R.transpose() * pd.R - Eigen::Matrix3d::Identity()).norm(), 1e-12);
    EXPECT_LT((pd.R * pd.S - F).norm(), 1e-12 * F.norm());
    EXPECT_LT((pd.S - pd.S.transpose()).norm(), 1e-14 * F.norm());
    // With at most one zero singular value, the proper-rotation form is unique as well (the sign on the
    // null direction is fixed by det R = 1), so it equals the oracle's.
    EXPECT_LT((pd.R - R).norm(), 1e-9);
    EXPECT_LT((pd.S - S).norm(), 1e-9 * F.norm());
    // The sign of det F decides which form SciPy's (U, P) is. Where det F is at round-off level (rank 2),
    // that sign is arbitrary and so is U's improper part; only P is unique there, and then S = P.
    const double detScale = std::pow(F.norm(), 3);
    const Eigen::Matrix3d P = fromJson(answer["polar"][k]["P"], 3);
    if (std::abs(F.determinant()) <= 1e-12 * detScale) {
      EXPECT_LT((pd.S - P).norm(), 1e-9 * F.norm());
      EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(pd.S).eigenvalues().minCoeff(), -1e-12 * F.norm());
    } else if (F.determinant() > 0.0) {  // R S is then the classical polar decomposition, identical to SciPy's
      EXPECT_LT((pd.R - fromJson(answer["polar"][k]["U"], 3)).norm(), 1e-9);
      EXPECT_LT((pd.S - P).norm(), 1e-9 * F.norm());
    }
  }
}

TEST(ScipyOracle, KabschMatchesScipyAlignVectorsIncludingReflections) {
  std::srand(43);
  struct KabschCase {
    std::string label;
    Eigen::Matrix3Xd x, y;
    Eigen::VectorXd w;
  };
  std::vector<KabschCase> cases;
  const Eigen::Matrix3Xd cloud = Eigen::Matrix3Xd::Random(3, 25);
  const Eigen::Vector3d shift(0.5, -1.0, 2.0);
  const Eigen::Matrix3d Q = randomRotation();
  cases.push_back({"exact rigid", cloud, (Q * cloud).colwise() + shift, Eigen::VectorXd::Ones(25)});
  cases.push_back({"noisy rigid, weighted", cloud,
                   ((Q * cloud).colwise() + shift) + 0.05 * Eigen::Matrix3Xd::Random(3, 25),
                   Eigen::VectorXd::Random(25).cwiseAbs()});
  Eigen::VectorXd someZero = Eigen::VectorXd::Random(25).cwiseAbs();
  someZero.head(10).setZero();
  cases.push_back({"deformed, zero weights", cloud,
                   withSingularValues({1.3, 0.9, 0.7}) * cloud + 0.1 * Eigen::Matrix3Xd::Random(3, 25), someZero});
  // The best orthogonal map is a reflection: the fix must flip the weakest axis, as SciPy does.
  const Eigen::Matrix3d mirror = Q * Eigen::Vector3d(1.0, 1.0, -1.0).asDiagonal();
  cases.push_back({"mirrored", cloud, mirror * cloud, Eigen::VectorXd::Ones(25)});
  const Eigen::Matrix3Xd flatCloud = Eigen::Vector3d(1.0, 0.6, 0.02).asDiagonal() * cloud;
  cases.push_back({"mirrored flattish", flatCloud, (Q * Eigen::Vector3d(-1.0, 1.0, 1.0).asDiagonal() * flatCloud).colwise() + shift,
                   Eigen::VectorXd::Ones(25)});
  Eigen::Matrix3Xd planar = cloud;
  planar.row(2).setZero();
  cases.push_back({"coplanar", planar, (Q * planar).colwise() + shift, Eigen::VectorXd::Ones(25)});
  const Eigen::Matrix3Xd triangle = Eigen::Matrix3Xd::Random(3, 3);
  cases.push_back({"triangle", triangle, Q * withSingularValues({1.1, 0.9, 1.0}) * triangle, Eigen::VectorXd::Ones(3)});

  json request;
  request["kabsch"] = json::array();
  for (const auto& c : cases) {
    request["kabsch"].push_back({{"x", colMajor(c.x)}, {"y", colMajor(c.y)}, {"w", colMajor(c.w)}});
  }
  const json answer = runOracle(request, "kabsch");
  ASSERT_EQ(answer.value("kabsch", json::array()).size(), cases.size());
  for (size_t k = 0; k < cases.size(); ++k) {
    SCOPED_TRACE(cases[k].label);
    const auto rt = kinematics::kabsch(cases[k].x, cases[k].y, cases[k].w);
    EXPECT_TRUE(rt.unique);
    EXPECT_LT((rt.R - fromJson(answer["kabsch"][k]["R"], 3)).norm(), 1e-9);
    EXPECT_LT((rt.t - fromJson(answer["kabsch"][k]["t"], 3)).norm(), 1e-9);
    EXPECT_NEAR(rt.R.determinant(), 1.0, 1e-12);
  }
  // exact rigid motion is recovered
  const auto exact = kinematics::kabsch(cases[0].x, cases[0].y);
  EXPECT_LT((exact.R - Q).norm(), 1e-12);
  EXPECT_LT((exact.t - shift).norm(), 1e-12);
}
