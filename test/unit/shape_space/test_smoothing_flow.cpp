// The smoothing flow (eq. 2): monotone path energy (eq. 4), closed curves contract, stationary points
// satisfy eq. 3, eq. 3 is the gradient of eq. 4, flow tangents descend (Lemma 2), restoring force,
// proportion-preserving weights, reduced mode, bad input.
#include <gtest/gtest.h>

#include <cmath>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/shape_space/discrete_shells.hpp"
#include "deformation_enrichment/shape_space/path_energy.hpp"
#include "deformation_enrichment/shape_space/smoothing_flow.hpp"
#include "flow_test_sequences.hpp"

namespace ss = deformation_enrichment::shape_space;
namespace de = deformation_enrichment;
using namespace ss::test;

namespace {

struct FlowSetup {
  FlatMesh base = bumpyGrid(5, 21);
  ss::DiscreteShells energy{base.triangles, base.vertices.size() / 3, ss::DiscreteShellsOptions::classic()};
  int serial = (energy.setThreadCount(1), 1);  // tiny meshes: OpenMP overhead would dominate
  ss::ShapeSequence sequence(int m, double noise, unsigned seed = 3) const {
    return ss::ShapeSequence{base.triangles, noisyBending(base, m, 0.2, 2.5, noise, seed)};
  }
};

double distance(const std::vector<Eigen::VectorXd>& a, const std::vector<Eigen::VectorXd>& b) {
  double d = 0.0;
  for (size_t i = 0; i < a.size(); ++i) d += (a[i] - b[i]).squaredNorm();
  return std::sqrt(d);
}

}  // namespace

TEST(SmoothingFlow, PathEnergyDecreasesEveryStep) {
  FlowSetup s;
  for (int variant = 0; variant < 3; ++variant) {
    ss::FlowOptions opt;
    opt.tau = 0.8;
    if (variant == 1) opt.weights = ss::FlowWeights::ProportionPreserving;
    if (variant == 2) {
      opt.reduction.reduced = true;
      opt.reduction.subspaceDimension = 6;
    }
    ss::SmoothingFlow flow(s.energy, s.sequence(7, 0.02), opt);
    double previous = flow.pathEnergy();
    const double initial = previous;
    for (int k = 0; k < 6; ++k) {
      const ss::FlowStep step = flow.step();
      ASSERT_FALSE(step.stalled) << "variant " << variant << " step " << k;
      EXPECT_LT(step.pathEnergy, previous) << "variant " << variant << " step " << k;
      EXPECT_NEAR(step.pathEnergy, flow.pathEnergy(), 1e-12 * initial);
      previous = step.pathEnergy;
    }
    EXPECT_LT(previous, 0.5 * initial) << "variant " << variant;  // the noise is mostly gone
  }
}

TEST(SmoothingFlow, PathGradientIsTheGradientOfThePathEnergy) {
  FlowSetup s;
  ss::FlowOptions opt;
  ss::SmoothingFlow flow(s.energy, s.sequence(5, 0.02), opt);
  const auto gradients = flow.pathGradient();
  EXPECT_EQ(gradients.front().norm(), 0.0);  // fixed ends
  const int i = 2;
  const double h = 1e-6;
  for (Eigen::Index k = 0; k < gradients[i].size(); k += 5) {
    auto p = flow.current().shapes, m = p;
    p[i][k] += h;
    m[i][k] -= h;
    const double fd = (flow.pathEnergy(p) - flow.pathEnergy(m)) / (2 * h);
    EXPECT_NEAR(gradients[i][k], fd, 1e-6 * (1 + std::abs(fd))) << "coordinate " << k;
  }
}

TEST(SmoothingFlow, FlowTangentIsADescentDirection) {  // Lemma 2 via eq. 9
  FlowSetup s;
  const auto shapes = s.sequence(5, 0.02).shapes;
  const auto tangents = ss::flowTangents(s.energy, shapes, false);
  ss::SmoothingFlow flow(s.energy, ss::ShapeSequence{s.base.triangles, shapes}, {});
  const auto gradients = flow.pathGradient();
  double slope = 0.0;
  for (size_t i = 0; i < shapes.size(); ++i) slope += gradients[i].dot(tangents[i]);
  EXPECT_LT(slope, 0.0);
  EXPECT_EQ(tangents.back().norm(), 0.0);
}

TEST(SmoothingFlow, ClosedSequenceContractsToAConstantShape) {  // [Brandt16 Fig. 4]
  FlowSetup s;
  std::vector<Eigen::VectorXd> shapes;
  const int m = 6;
  for (int k = 0; k < m; ++k) shapes.push_back(bent(s.base.vertices, 1.5 * std::sin(2 * M_PI * k / m), 0.05 * std::cos(2 * M_PI * k / m)));
  ss::FlowOptions opt;
  opt.closed = true;
  opt.tau = 1.0;
  ss::SmoothingFlow flow(s.energy, ss::ShapeSequence{s.base.triangles, shapes}, opt);
  const double initial = flow.pathEnergy();
  for (int k = 0; k < 10; ++k) flow.step();
  EXPECT_LT(flow.pathEnergy(), 1e-3 * initial);
  // Every shape is close to every other (the curve became a point), up to rigid motion: check the energy.
  for (int k = 1; k < m; ++k)
    EXPECT_LT(s.energy.value(flow.current().shapes[0], flow.current().shapes[size_t(k)]), 1e-3 * initial);
}

TEST(SmoothingFlow, StationaryPointsSatisfyEquation3) {
  FlowSetup s;
  ss::FlowOptions opt;
  opt.tau = 1.0;
  opt.symmetricAverage = true;  // the flow's fixed points are exactly the critical points of eq. 4
  ss::SmoothingFlow flow(s.energy, s.sequence(5, 0.02), opt);
  const double initial = flow.reducedPathGradientSquaredNorm();
  int steps = 0;
  while (steps < 400 && flow.reducedPathGradientSquaredNorm() > 1e-14 * initial) {
    if (flow.step().stalled) break;
    ++steps;
  }
  EXPECT_LT(flow.reducedPathGradientSquaredNorm(), 1e-10 * initial) << steps << " steps";
  // And a further flow step leaves the (stationary) curve in place.
  const auto before = flow.current().shapes;
  flow.step();
  EXPECT_LT(distance(before, flow.current().shapes), 1e-5 * std::sqrt(double(before.size())) * before[0].norm());
}

TEST(SmoothingFlow, RestoringForceKeepsShapesNearTheInput) {
  FlowSetup s;
  const ss::ShapeSequence input = s.sequence(7, 0.02);
  const auto run = [&](double rho, std::vector<int> selected) {
    ss::FlowOptions opt;
    opt.rho = rho;
    opt.restoredShapes = std::move(selected);
    ss::SmoothingFlow flow(s.energy, input, opt);
    for (int k = 0; k < 5; ++k) flow.step();
    return flow.current().shapes;
  };
  const auto free = run(0.0, {});
  const auto all = run(0.5, {});
  const auto one = run(0.5, {3});
  EXPECT_LT(distance(all, input.shapes), 0.8 * distance(free, input.shapes));
  EXPECT_LT((one[3] - input.shapes[3]).norm(), 0.8 * (free[3] - input.shapes[3]).norm());
  EXPECT_THROW(run(0.5, {9}), de::InvalidInputError);
}

TEST(SmoothingFlow, ProportionPreservingWeightsKeepSegmentRatios) {
  FlowSetup s;
  // Unevenly spaced bending (parameter s^2): fixed weights equalise the segments, the proportional ones not.
  std::vector<Eigen::VectorXd> shapes;
  const int m = 6;
  for (int k = 0; k < m; ++k) {
    const double u = std::pow(double(k) / (m - 1), 2.0);
    shapes.push_back(bent(s.base.vertices, 0.2 + 2.3 * u, 0.1 * u));
  }
  const auto ratio = [&](const std::vector<Eigen::VectorXd>& x) {  // last segment length / first
    return std::sqrt(s.energy.value(x[m - 2], x[m - 1])) / std::sqrt(s.energy.value(x[0], x[1]));
  };
  const double original = ratio(shapes);
  double after[2];
  for (int variant = 0; variant < 2; ++variant) {
    ss::FlowOptions opt;
    opt.weights = variant ? ss::FlowWeights::ProportionPreserving : ss::FlowWeights::Fixed;
    ss::SmoothingFlow flow(s.energy, ss::ShapeSequence{s.base.triangles, shapes}, opt);
    for (int k = 0; k < 10; ++k) flow.step();
    after[variant] = ratio(flow.current().shapes);
  }
  EXPECT_GT(original, 3.0);
  EXPECT_LT(std::abs(std::log(after[1] / original)), 0.5 * std::abs(std::log(after[0] / original)));
}

// A frame that is a rigid copy of its neighbour costs nothing (rigid invariance): the flow runs as usual.
// A sequence of rigid copies of one shape has eq. 4 = 0, so no step can lower it: every step stalls and
// the (finite) input stays.
TEST(SmoothingFlow, RigidCopiesAreNothingToSmooth) {
  FlowSetup s;
  ss::ShapeSequence input = s.sequence(5, 0.01);
  input.shapes[2] = moved(input.shapes[1], someRotation(0.4), Eigen::Vector3d(0.3, -0.2, 0.1));
  for (bool reduced : {false, true}) {
    ss::FlowOptions opt;
    opt.reduction.reduced = reduced;
    ss::SmoothingFlow flow(s.energy, input, opt);
    const double before = flow.pathEnergy();
    const ss::FlowStep step = flow.step();
    EXPECT_FALSE(step.stalled) << "reduced " << reduced;
    EXPECT_LT(flow.pathEnergy(), before);
  }
  ss::ShapeSequence copies = input;
  for (size_t i = 0; i < copies.shapes.size(); ++i)
    copies.shapes[i] = moved(input.shapes[1], someRotation(0.3 * double(i)), Eigen::Vector3d(0.1 * double(i), 0.0, 0.0));
  for (bool reduced : {false, true}) {
    ss::FlowOptions opt;
    opt.reduction.reduced = reduced;
    ss::SmoothingFlow flow(s.energy, copies, opt);
    EXPECT_NEAR(flow.pathEnergy(), 0.0, 1e-20);
    const ss::FlowStep step = flow.step();
    EXPECT_TRUE(step.stalled) << "reduced " << reduced;
    for (size_t i = 0; i < copies.shapes.size(); ++i) EXPECT_EQ(flow.current().shapes[i], copies.shapes[i]);
  }
}

TEST(SmoothingFlow, BadInputGivesClearErrors) {
  FlowSetup s;
  ss::ShapeSequence two = s.sequence(3, 0.0);
  two.shapes.pop_back();
  EXPECT_THROW(ss::SmoothingFlow(s.energy, two, {}), de::InvalidInputError);
  ss::ShapeSequence nan = s.sequence(4, 0.0);
  nan.shapes[2][5] = std::nan("");
  EXPECT_THROW(ss::SmoothingFlow(s.energy, nan, {}), de::InvalidInputError);
  ss::ShapeSequence ragged = s.sequence(4, 0.0);
  ragged.shapes[1].conservativeResize(ragged.shapes[1].size() - 3);
  EXPECT_THROW(ss::SmoothingFlow(s.energy, ragged, {}), de::InvalidInputError);
  ss::FlowOptions opt;
  opt.tau = 1.5;
  EXPECT_THROW(ss::SmoothingFlow(s.energy, s.sequence(4, 0.0), opt), de::InvalidInputError);
  opt.tau = 0.5;
  opt.rho = 1.0;
  EXPECT_THROW(ss::SmoothingFlow(s.energy, s.sequence(4, 0.0), opt), de::InvalidInputError);
  ss::ShapeSequence flat = s.sequence(4, 0.0);  // a triangle collapsed exactly onto a line
  const Eigen::Vector3i t = flat.triangles.col(0);
  flat.shapes[1].segment<3>(3 * t[2]) = 0.5 * (flat.shapes[1].segment<3>(3 * t[0]) + flat.shapes[1].segment<3>(3 * t[1]));
  try {
    ss::SmoothingFlow(s.energy, flat, {});
    FAIL() << "degenerate triangle accepted";
  } catch (const de::InvalidInputError& e) {
    EXPECT_NE(std::string(e.what()).find("shape 1"), std::string::npos) << e.what();
  }
}
