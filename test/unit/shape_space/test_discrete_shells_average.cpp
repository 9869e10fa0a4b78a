// DiscreteShells::weightedReferences: the aggregated eq. 10 objective equals the sum of the terms (value,
// gradient and Hessian), its gradient matches finite differences, and bad input is rejected.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <vector>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/shape_space/dihedral_angle.hpp"
#include "deformation_enrichment/shape_space/discrete_shells.hpp"
#include "shell_test_meshes.hpp"

namespace ss = deformation_enrichment::shape_space;
namespace de = deformation_enrichment;
using namespace ss::test;

namespace {

// Three perturbed copies of a mesh as the references of an average, with pointers for the interface.
struct References {
  References(const FlatMesh& mesh, double amplitude, unsigned seed)
      : shapes{perturbed(mesh.vertices, amplitude, seed), perturbed(mesh.vertices, amplitude, seed + 1),
               perturbed(mesh.vertices, amplitude, seed + 2)},
        pointers{&shapes[0], &shapes[1], &shapes[2]} {}
  std::vector<Eigen::VectorXd> shapes;
  std::vector<const Eigen::VectorXd*> pointers;
};

// Runs check(energy) with the classic and the hyperelastic membrane on `mesh`.
template <class Check>
void forBothMembranes(const FlatMesh& mesh, const Check& check) {
  for (const auto& parameters : {ss::DiscreteShellsOptions::classic(), ss::DiscreteShellsOptions::hyperelastic(0.05)})
    check(ss::DiscreteShells(mesh.triangles, mesh.vertices.size() / 3, parameters));
}

}  // namespace

TEST(WeightedReferences, EqualTheSumOfTermsForBothMembranesWithGradient) {
  const FlatMesh mesh = bumpyGrid(6, 4);
  const References references(mesh, 0.03, 1);
  const std::vector<double> weights{0.25, 0.0, 0.6};
  const Eigen::VectorXd y = perturbed(mesh.vertices, 0.04, 9);
  forBothMembranes(mesh, [&](const ss::DiscreteShells& energy) {
    double sum = 0.0;
    Eigen::VectorXd gradientSum = Eigen::VectorXd::Zero(y.size());
    for (size_t i = 0; i < references.shapes.size(); ++i) {
      sum += weights[i] * energy.value(references.shapes[i], y);
      gradientSum += weights[i] * energy.gradientDeformed(references.shapes[i], y);
    }
    const auto aggregated = energy.weightedReferences(weights, references.pointers);
    ASSERT_TRUE(aggregated);
    Eigen::VectorXd gradient;
    EXPECT_NEAR(aggregated->evaluate(y, &gradient), sum, 1e-11 * sum);
    EXPECT_NEAR(aggregated->evaluate(y, nullptr), sum, 1e-11 * sum);
    EXPECT_LT((gradient - gradientSum).norm(), 1e-10 * gradientSum.norm());
    // Finite differences of the aggregated value itself.
    const double h = 1e-6;
    for (Eigen::Index i : {Eigen::Index(0), Eigen::Index(40), y.size() - 2}) {
      Eigen::VectorXd plus = y, minus = y;
      plus[i] += h;
      minus[i] -= h;
      const double fd = (aggregated->evaluate(plus, nullptr) - aggregated->evaluate(minus, nullptr)) / (2 * h);
      EXPECT_NEAR(gradient[i], fd, 1e-6 * std::max(1.0, std::abs(fd)));
    }
  });
}

// Noisy hinges (as on real captures): the references' dihedral angles spread by more than pi/2, where the
// aggregated form Omega (theta - theta_star)^2 alone would be wrong (the energy wraps each difference).
TEST(WeightedReferences, EqualTheSumOfTermsWhereReferenceAnglesSpreadWidely) {
  const FlatMesh mesh = bumpyGrid(6, 4);
  const References references(mesh, 0.12, 11);
  const std::vector<double> weights{0.3, 0.45, 0.25};
  const ss::DiscreteShells energy(mesh.triangles, mesh.vertices.size() / 3, ss::DiscreteShellsOptions::classic());
  int spread = 0;
  for (const Eigen::Vector4i& h : energy.hinges()) {
    const auto angle = [&h](const Eigen::VectorXd& r) {
      return ss::dihedralAngle(r.segment<3>(3 * h[0]), r.segment<3>(3 * h[1]), r.segment<3>(3 * h[2]), r.segment<3>(3 * h[3]));
    };
    double lo = 10.0, hi = -10.0;
    for (const auto& r : references.shapes) {
      const double t = std::remainder(angle(r) - angle(references.shapes[0]), 2.0 * M_PI);
      lo = std::min(lo, t);
      hi = std::max(hi, t);
    }
    spread += hi - lo > 0.5 * M_PI ? 1 : 0;
  }
  ASSERT_GT(spread, 0) << "the references do not exercise widely spread hinges";
  const auto aggregated = energy.weightedReferences(weights, references.pointers);
  for (unsigned seed : {21u, 22u, 23u, 24u}) {
    const Eigen::VectorXd y = perturbed(mesh.vertices, 0.12, seed);
    double sum = 0.0;
    Eigen::VectorXd gradientSum = Eigen::VectorXd::Zero(y.size());
    for (size_t i = 0; i < references.shapes.size(); ++i) {
      sum += weights[i] * energy.value(references.shapes[i], y);
      gradientSum += weights[i] * energy.gradientDeformed(references.shapes[i], y);
    }
    Eigen::VectorXd gradient;
    EXPECT_NEAR(aggregated->evaluate(y, &gradient), sum, 1e-11 * sum) << "seed " << seed;
    EXPECT_LT((gradient - gradientSum).norm(), 1e-10 * gradientSum.norm()) << "seed " << seed;
  }
}

TEST(WeightedReferences, HessianEqualsTheSumOfTheTermsHessians) {
  const FlatMesh mesh = bumpyGrid(6, 4);
  // Mild and wide-spread reference angles: both branches of the bending term.
  for (double amplitude : {0.03, 0.12}) {
    const References references(mesh, amplitude, 1);
    const std::vector<double> weights{0.25, 0.15, 0.6};
    const Eigen::VectorXd y = perturbed(mesh.vertices, amplitude, 9);
    forBothMembranes(mesh, [&](const ss::DiscreteShells& energy) {
      Eigen::MatrixXd sum = Eigen::MatrixXd::Zero(y.size(), y.size());
      for (size_t i = 0; i < references.shapes.size(); ++i) sum += weights[i] * Eigen::MatrixXd(energy.hessianDeformed(references.shapes[i], y));
      const Eigen::MatrixXd aggregated(energy.weightedReferences(weights, references.pointers)->hessian(y));
      EXPECT_LT((aggregated - sum).norm(), 1e-9 * sum.norm()) << "amplitude " << amplitude;
    });
  }
}

TEST(WeightedReferences, BadInputGivesClearErrors) {
  const FlatMesh mesh = bumpyGrid(4, 4);
  const ss::DiscreteShells energy(mesh.triangles, mesh.vertices.size() / 3);
  const Eigen::VectorXd x = mesh.vertices;
  EXPECT_THROW(energy.weightedReferences({1.0, 2.0}, {&x}), de::InvalidInputError);
  EXPECT_THROW(energy.weightedReferences({-1.0}, {&x}), de::InvalidInputError);
  Eigen::VectorXd nan = x;
  nan[3] = std::nan("");
  EXPECT_THROW(energy.weightedReferences({1.0}, {&nan}), de::InvalidInputError);
  const Eigen::VectorXd shorter = x.head(x.size() - 3);
  EXPECT_THROW(energy.weightedReferences({1.0}, {&shorter}), de::InvalidInputError);
  Eigen::VectorXd flat = x;  // triangle 0 = (0, 1, 5): vertex 5 moved onto the segment 0-1
  flat.segment<3>(15) = 0.5 * (x.segment<3>(0) + x.segment<3>(3));
  EXPECT_THROW(energy.weightedReferences({1.0}, {&flat}), de::InvalidInputError);
  const auto aggregated = energy.weightedReferences({1.0}, {&x});
  EXPECT_THROW(aggregated->evaluate(flat, nullptr), de::InvalidInputError);
  EXPECT_THROW(aggregated->evaluate(nan, nullptr), de::InvalidInputError);
  EXPECT_THROW(aggregated->evaluate(shorter, nullptr), de::InvalidInputError);
  EXPECT_THROW(aggregated->hessian(flat), de::InvalidInputError);
  EXPECT_THROW(aggregated->hessian(nan), de::InvalidInputError);
}

// Reference data computed once per shape (referenceData) and passed in gives the same objective, bit for bit,
// as computing it inside (the smoothing flow shares it between the averages of a step).
TEST(WeightedReferences, SharedReferenceDataGivesTheSameObjective) {
  const FlatMesh mesh = bumpyGrid(6, 4);
  const References references(mesh, 0.05, 3);
  const Eigen::VectorXd y = perturbed(mesh.vertices, 0.04, 7);
  forBothMembranes(mesh, [&](const ss::DiscreteShells& energy) {
    const std::vector<double> weights{0.3, 0.5, 0.2};
    std::vector<std::shared_ptr<const ss::ReferenceData>> kept;
    for (const Eigen::VectorXd& shape : references.shapes) kept.push_back(energy.referenceData(shape));
    // All shared, and one left to be computed inside (null).
    for (const std::vector<const ss::ReferenceData*>& data :
         {std::vector<const ss::ReferenceData*>{kept[0].get(), kept[1].get(), kept[2].get()},
          std::vector<const ss::ReferenceData*>{kept[0].get(), nullptr, kept[2].get()}}) {
      Eigen::VectorXd gradient, gradientShared;
      const double value = energy.weightedReferences(weights, references.pointers)->evaluate(y, &gradient);
      EXPECT_EQ(energy.weightedReferences(weights, references.pointers, data)->evaluate(y, &gradientShared), value);
      EXPECT_EQ(gradientShared, gradient);
    }
  });
}

TEST(WeightedReferences, ReferenceDataOfAnotherEnergyIsRejected) {
  const FlatMesh mesh = bumpyGrid(5, 4), other = bumpyGrid(4, 4);
  const Eigen::VectorXd x = mesh.vertices;
  const ss::DiscreteShells classic(mesh.triangles, mesh.vertices.size() / 3, ss::DiscreteShellsOptions::classic());
  const ss::DiscreteShells hyperelastic(mesh.triangles, mesh.vertices.size() / 3, ss::DiscreteShellsOptions::hyperelastic(0.05));
  const ss::DiscreteShells smaller(other.triangles, other.vertices.size() / 3, ss::DiscreteShellsOptions::classic());
  // The other membrane: no edge lengths, and hinge weights with another factor.
  const auto hyperelasticData = hyperelastic.referenceData(x);
  EXPECT_THROW(classic.weightedReferences({1.0}, {&x}, {hyperelasticData.get()}), de::InvalidInputError);
  const Eigen::VectorXd y = other.vertices;
  const auto smallerData = smaller.referenceData(y);  // another mesh
  EXPECT_THROW(classic.weightedReferences({1.0}, {&x}, {smallerData.get()}), de::InvalidInputError);
  const auto classicData = classic.referenceData(x);
  EXPECT_THROW(classic.weightedReferences({1.0}, {&x}, {classicData.get(), classicData.get()}), de::InvalidInputError);
  EXPECT_THROW(hyperelastic.weightedReferences({1.0}, {&x}, {classicData.get()}), de::InvalidInputError);
  EXPECT_NO_THROW(classic.weightedReferences({1.0}, {&x}, {classicData.get()}));
  Eigen::VectorXd nan = x;
  nan[0] = std::nan("");
  EXPECT_THROW(classic.referenceData(nan), de::InvalidInputError);
}
