// Properties of the Discrete Shells energies: zero at the reference, rigid-motion invariance, the external
// GOAST parity value, serial == parallel, and the documented behaviour on non-manifold, inconsistently
// oriented, degenerate and malformed input.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <limits>
#include <string>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/mesh_io.hpp"
#include "deformation_enrichment/shape_space/discrete_shells.hpp"
#include "shell_test_meshes.hpp"

namespace deformation_enrichment::shape_space {
namespace {

using Eigen::VectorXd;


VectorXd rigidlyMoved(const VectorXd& shape, const Eigen::Matrix3d& rotation, const Eigen::Vector3d& translation) {
  VectorXd out(shape.size());
  for (Eigen::Index v = 0; v < shape.size() / 3; ++v) out.segment<3>(3 * v) = rotation * shape.segment<3>(3 * v) + translation;
  return out;
}

VectorXd flatten(const Eigen::Matrix3Xd& vertices) { return Eigen::Map<const VectorXd>(vertices.data(), vertices.size()); }

const DiscreteShellsOptions kModels[] = {DiscreteShellsOptions::hyperelastic(0.01), DiscreteShellsOptions::classic()};

TEST(DiscreteShells, ZeroEnergyAndGradientsAtTheReference) {
  for (const auto& parameters : kModels) {
    for (const test::FlatMesh& mesh : {test::bumpyGrid(6, 1), test::octahedron()}) {
      const DiscreteShells energy(mesh.triangles, mesh.vertices.size() / 3, parameters);
      const test::AllOutputs r = test::evaluateAll(energy, mesh.vertices, mesh.vertices);
      EXPECT_NEAR(r.value, 0.0, 1e-13);
      EXPECT_LT(r.gradientDeformed.cwiseAbs().maxCoeff(), 1e-12);
      EXPECT_LT(r.gradientReference.cwiseAbs().maxCoeff(), 1e-12);
      // At the minimum the deformed Hessian is positive semi-definite (rigid motions in its kernel).
      const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(Eigen::MatrixXd(r.hessianDeformed));
      EXPECT_GT(eig.eigenvalues().minCoeff(), -1e-10);
      // And the energy grows away from it.
      EXPECT_GT(energy.value(mesh.vertices, test::perturbed(mesh.vertices, 0.01, 5)), 1e-8);
    }
  }
}

TEST(DiscreteShells, InvariantToRigidMotionsOfEitherArgument) {
  const Eigen::Matrix3d rotation =
      Eigen::AngleAxisd(1.1, Eigen::Vector3d(0.3, -0.5, 0.8).normalized()).toRotationMatrix();
  const Eigen::Vector3d translation(2.0, -1.0, 0.5);
  for (const auto& parameters : kModels) {
    const test::FlatMesh mesh = test::bumpyGrid(6, 2);
    const DiscreteShells energy(mesh.triangles, mesh.vertices.size() / 3, parameters);
    const VectorXd reference = mesh.vertices;
    const VectorXd deformed = test::perturbed(reference, 0.05, 9);
    const test::AllOutputs base = test::evaluateAll(energy, reference, deformed);
    ASSERT_GT(base.value, 1e-4);
    const VectorXd movedDeformed = rigidlyMoved(deformed, rotation, translation);
    const VectorXd movedReference = rigidlyMoved(reference, rotation.transpose(), -translation);
    EXPECT_NEAR(energy.value(reference, movedDeformed), base.value, 1e-12 * base.value);
    EXPECT_NEAR(energy.value(movedReference, deformed), base.value, 1e-12 * base.value);
    EXPECT_NEAR(energy.value(movedReference, movedDeformed), base.value, 1e-12 * base.value);
    // The deformed gradient turns with the deformed shape: dW/dx(R x + t) = R dW/dx(x) per vertex.
    const VectorXd turned = energy.gradientDeformed(reference, movedDeformed);
    const VectorXd expected = rigidlyMoved(base.gradientDeformed, rotation, Eigen::Vector3d::Zero());
    EXPECT_LT((turned - expected).cwiseAbs().maxCoeff(), 1e-10 * base.gradientDeformed.cwiseAbs().maxCoeff());
    // Rigid motions are in the kernel of the Hessian's action on the gradient: sum of forces vanishes.
    Eigen::Vector3d force = Eigen::Vector3d::Zero();
    for (Eigen::Index v = 0; v < deformed.size() / 3; ++v) force += base.gradientDeformed.segment<3>(3 * v);
    EXPECT_LT(force.norm(), 1e-12 * base.gradientDeformed.norm() * deformed.size());
  }
}

TEST(DeformationEnergy, SeveralOutputsInOneCallMatchTheSingleCalls) {
  const test::FlatMesh mesh = test::bumpyGrid(5, 3);
  const DiscreteShells shells(mesh.triangles, 25, DiscreteShellsOptions::classic());
  const test::ForwardingEnergy forwarding(shells);
  const VectorXd deformed = test::perturbed(mesh.vertices, 0.05, 6);
  for (const DeformationEnergy* energy : {static_cast<const DeformationEnergy*>(&shells),
                                          static_cast<const DeformationEnergy*>(&forwarding)}) {
    double value = -1.0;
    VectorXd gradient;
    Eigen::SparseMatrix<double> hessian, mixed;
    energy->evaluate(mesh.vertices, deformed, {&value, &gradient, nullptr, &hessian, &mixed, nullptr});
    EXPECT_NEAR(value, shells.value(mesh.vertices, deformed), 1e-14 * value);
    EXPECT_LT((gradient - shells.gradientDeformed(mesh.vertices, deformed)).norm(), 1e-13 * gradient.norm());
    EXPECT_LT((hessian - shells.hessianDeformed(mesh.vertices, deformed)).norm(), 1e-13 * hessian.norm());
    EXPECT_LT((mixed - shells.hessianMixed(mesh.vertices, deformed)).norm(), 1e-13 * mixed.norm());
    EXPECT_GT(value, 0.0);
  }
}

TEST(DiscreteShells, SerialAndParallelEvaluationsAgree) {
  const test::FlatMesh mesh = test::bumpyGrid(12, 4);
  DiscreteShells energy(mesh.triangles, mesh.vertices.size() / 3, DiscreteShellsOptions::hyperelastic());
  const VectorXd deformed = test::perturbed(mesh.vertices, 0.03, 8);
  energy.setThreadCount(1);
  const test::AllOutputs serial = test::evaluateAll(energy, mesh.vertices, deformed);
  energy.setThreadCount(3);
  const test::AllOutputs parallel = test::evaluateAll(energy, mesh.vertices, deformed);
  EXPECT_NEAR(serial.value, parallel.value, 1e-12 * serial.value);
  EXPECT_LT((serial.gradientDeformed - parallel.gradientDeformed).norm(), 1e-12 * serial.gradientDeformed.norm());
  EXPECT_LT((serial.gradientReference - parallel.gradientReference).norm(), 1e-12 * serial.gradientReference.norm());
  EXPECT_LT((serial.hessianDeformed - parallel.hessianDeformed).norm(), 1e-12 * serial.hessianDeformed.norm());
  EXPECT_LT((serial.hessianMixed - parallel.hessianMixed).norm(), 1e-12 * serial.hessianMixed.norm());
  EXPECT_LT((serial.hessianReference - parallel.hessianReference).norm(), 1e-12 * serial.hessianReference.norm());
  EXPECT_THROW(energy.setThreadCount(0), InvalidInputError);

  // Called from inside an outer parallel region (as a flow evaluating several shapes at once does), the
  // inner loop gets a team of one thread: results must not change.
  double nestedValue[2] = {0.0, 0.0};
  Eigen::VectorXd nestedGradient[2];
#pragma omp parallel for num_threads(2)
  for (int i = 0; i < 2; ++i) {
    const test::AllOutputs r = test::evaluateAll(energy, mesh.vertices, deformed, false);
    nestedValue[i] = r.value;
    nestedGradient[i] = r.gradientDeformed;
  }
  for (int i = 0; i < 2; ++i) {
    EXPECT_NEAR(nestedValue[i], serial.value, 1e-12 * serial.value);
    ASSERT_EQ(nestedGradient[i].size(), serial.gradientDeformed.size());
    EXPECT_LT((nestedGradient[i] - serial.gradientDeformed).norm(), 1e-12 * serial.gradientDeformed.norm());
  }
}

// docs/design.md §4: GOAST evaluates W[finger0, finger1] = 0.0919995 (hyperelastic membrane, mu = lambda = 1,
// bending l^2 / (a1 + a2) weighted by delta = 0.001).
TEST(DiscreteShells, MatchesGoastOnTheFingerPair) {
  const std::string directory = std::string(DE_SOURCE_DIR) + "/test/data/finger/";  // [finger], shipped
  const mesh::TriangleMesh finger0 = mesh::readTriangleMesh(directory + "finger0.ply");
  const mesh::TriangleMesh finger1 = mesh::readTriangleMesh(directory + "finger1.ply");
  ASSERT_EQ(finger0.triangles, finger1.triangles);
  const DiscreteShells energy(finger0.triangles, finger0.numVertices(), DiscreteShellsOptions::hyperelastic(0.001));
  const double w = energy.value(flatten(finger0.vertices), flatten(finger1.vertices));
  std::cout << "W[finger0, finger1] = " << std::setprecision(10) << w << " (membrane "
            << energy.membraneValue(flatten(finger0.vertices), flatten(finger1.vertices)) << ", bending "
            << energy.bendingValue(flatten(finger0.vertices), flatten(finger1.vertices)) << ")\n";
  EXPECT_NEAR(w, 0.0919995, 1e-7);  // the published value has 7 significant digits
}

// Directional finite differences of every derivative on the real finger pair (2k vertices, a scanned-like
// surface rather than a synthetic grid), for both membranes.
TEST(DiscreteShells, DirectionalDerivativesOnTheFingerPair) {
  const std::string directory = std::string(DE_SOURCE_DIR) + "/test/data/finger/";  // [finger], shipped
  const mesh::TriangleMesh finger0 = mesh::readTriangleMesh(directory + "finger0.ply");
  const mesh::TriangleMesh finger1 = mesh::readTriangleMesh(directory + "finger1.ply");
  const VectorXd reference = flatten(finger0.vertices), deformed = flatten(finger1.vertices);
  const VectorXd direction = test::perturbed(VectorXd::Zero(reference.size()), 1.0, 17);
  const double h = 1e-6;
  for (const auto& parameters : kModels) {
    const DiscreteShells energy(finger0.triangles, finger0.numVertices(), parameters);
    const test::AllOutputs r = test::evaluateAll(energy, reference, deformed);
    auto relative = [](const VectorXd& a, const VectorXd& b) { return (a - b).norm() / b.norm(); };
    // Along the deformed argument.
    const test::AllOutputs plus = test::evaluateAll(energy, reference, deformed + h * direction);
    const test::AllOutputs minus = test::evaluateAll(energy, reference, deformed - h * direction);
    EXPECT_NEAR(r.gradientDeformed.dot(direction), (plus.value - minus.value) / (2 * h),
                1e-6 * std::abs(r.gradientDeformed.dot(direction)));
    EXPECT_LT(relative(r.hessianDeformed * direction, (plus.gradientDeformed - minus.gradientDeformed) / (2 * h)), 1e-6);
    EXPECT_LT(relative(r.hessianMixed * direction, (plus.gradientReference - minus.gradientReference) / (2 * h)), 1e-6);
    // Along the reference argument.
    const test::AllOutputs plusRef = test::evaluateAll(energy, reference + h * direction, deformed);
    const test::AllOutputs minusRef = test::evaluateAll(energy, reference - h * direction, deformed);
    EXPECT_NEAR(r.gradientReference.dot(direction), (plusRef.value - minusRef.value) / (2 * h),
                1e-6 * std::abs(r.gradientReference.dot(direction)));
    EXPECT_LT(relative(r.hessianReference * direction, (plusRef.gradientReference - minusRef.gradientReference) / (2 * h)),
              1e-6);
    EXPECT_LT(relative(VectorXd(r.hessianMixed.transpose() * direction),
                       (plusRef.gradientDeformed - minusRef.gradientDeformed) / (2 * h)),
              1e-6);
  }
}

}  // namespace
}  // namespace deformation_enrichment::shape_space
