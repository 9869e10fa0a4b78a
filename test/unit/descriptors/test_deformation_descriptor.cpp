#include <gtest/gtest.h>

#include <cstdio>
#include <functional>

#include "descriptor_test_support.hpp"
#include "deformation_enrichment/descriptors/descriptor_distance.hpp"
#include "deformation_enrichment/descriptors/descriptor_evaluator.hpp"
#include "deformation_enrichment/error.hpp"

using namespace deformation_enrichment;
using namespace deformation_enrichment::descriptors;

namespace {
using Mode = std::function<Eigen::Vector3d(const Eigen::Vector3d&)>;

// Paper 000 §6.2 setting: a cube of edge 2, contact at the centre of the top face.
const Eigen::Vector3d kTop(0.0, 0.0, 1.0);

const mesh::TetMesh& cube() {
  static const mesh::TetMesh mesh = de_test::uniformBox(Eigen::Vector3d(-1, -1, -1), Eigen::Vector3d(1, 1, 1), 10);
  return mesh;
}

DescriptorOptions cubeOptions() {
  DescriptorOptions options;
  options.window.scale = 0.2;  // cut-off 0.8 stays inside the top face: no edge in the window
  options.deformationOrder = 2;
  return options;
}

// Localised bump around the top centre.
double bump(const Eigen::Vector3d& x) {
  const double s = 0.3;
  return std::exp(-(x.x() * x.x() + x.y() * x.y() + (1.0 - x.z()) * (1.0 - x.z())) / (2.0 * s * s));
}

std::vector<std::pair<std::string, Mode>> syntheticModes() {
  const double a = 0.05, s = 0.3;
  std::vector<std::pair<std::string, Mode>> modes = {
      {"indent", [=](const Eigen::Vector3d& x) -> Eigen::Vector3d { return Eigen::Vector3d(0, 0, -a * bump(x)); }},
      {"pull", [=](const Eigen::Vector3d& x) -> Eigen::Vector3d { return Eigen::Vector3d(0, 0, a * bump(x)); }},
      {"drag x", [=](const Eigen::Vector3d& x) -> Eigen::Vector3d { return Eigen::Vector3d(a * bump(x), 0, 0); }},
      {"twist", [=](const Eigen::Vector3d& x) -> Eigen::Vector3d { return Eigen::Vector3d(-x.y(), x.x(), 0) * (a * bump(x) / s); }},
      {"spread", [=](const Eigen::Vector3d& x) -> Eigen::Vector3d { return Eigen::Vector3d(x.x(), x.y(), 0) * (a * bump(x) / s); }},
      {"squash", [=](const Eigen::Vector3d& x) -> Eigen::Vector3d { return Eigen::Vector3d(0, 0, -a * (x.z() + 1.0) / 2.0); }},
      {"oblique poke",
       [=](const Eigen::Vector3d& x) -> Eigen::Vector3d { return Eigen::Vector3d(1, 0, -1) * (a * bump(x) / std::sqrt(2.0)); }},
  };
  // Mode 8 = mode 7 rotated about the contact normal: u8(x) = Q u7(Q^T x).
  const Mode poke = modes.back().second;
  const Eigen::Matrix3d Q = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  modes.push_back({"poke rotated", [=](const Eigen::Vector3d& x) -> Eigen::Vector3d { return Eigen::Vector3d(Q * poke(Q.transpose() * x)); }});
  return modes;
}

Eigen::Matrix3Xd deform(const Eigen::Matrix3Xd& rest, const Mode& mode) {
  Eigen::Matrix3Xd deformed = rest;
  for (Eigen::Index v = 0; v < rest.cols(); ++v) deformed.col(v) += mode(rest.col(v));
  return deformed;
}
}  // namespace

TEST(DeformationDescriptor, RigidMotionIsRemovedByEq10) {
  std::mt19937 rng(23);
  const DescriptorEvaluator evaluator(cube(), cubeOptions());
  const Eigen::Matrix3d Q = de_test::randomRotation(rng);
  const Eigen::Matrix3Xd moved = (Q * cube().vertices).colwise() + Eigen::Vector3d(1.0, -2.0, 0.5);
  const ContactDescriptor contact = evaluator.evaluate(kTop, moved);
  ASSERT_TRUE(contact.deformation.has_value());
  EXPECT_LT((contact.deformation->R - Q).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((contact.deformation->F - Q).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT(contact.deformation->mu.values().cwiseAbs().maxCoeff(), 1e-13);
  const Eigen::Matrix3Xd uBar =
      rigidFreeDisplacement(cube().vertices, moved, contact.deformation->R, contact.deformation->t);
  EXPECT_LT(uBar.cwiseAbs().maxCoeff(), 1e-12) << "u_bar vanishes everywhere for a rigid motion";
}

TEST(DeformationDescriptor, RigidFreeDisplacementVanishesAtTheFitCentre) {
  // eq. (10) removes R and t = y_bar - R x_bar: for an affine deformation u_bar(x) = (S - I)(x - x_bar), so
  // u_bar(p) = 0 where p is the weighted centroid (an interior vertex of a uniform grid), and the weighted
  // mean of u_bar (mu_0) is zero everywhere.
  const DescriptorOptions options = cubeOptions();
  const DescriptorEvaluator evaluator(cube(), options);
  const PointSampling& sampling = evaluator.sampling();
  Eigen::Matrix3d A;
  A << 1.05, 0.1, -0.02, 0.03, 0.97, 0.08, -0.05, 0.02, 1.1;
  const Eigen::Vector3d c(0.2, 0.1, -0.3);
  const Eigen::Matrix3Xd affine = (A * sampling.points()).colwise() + c;
  const int centre = sampling.nearest(Eigen::Vector3d::Zero());
  const Window window = gatherWindow(sampling, sampling.points().col(centre), options.window);
  const DeformationDescriptor d = deformationDescriptor(window, sampling.points(), affine, 2);
  const Eigen::Matrix3Xd uBar = rigidFreeDisplacement(sampling.points(), affine, d.R, d.t);
  EXPECT_LT(uBar.col(centre).norm(), 1e-12);
  EXPECT_LT((d.F - A).cwiseAbs().maxCoeff(), 1e-12);

  // At a surface contact the fit centre x_bar lies inside, about h below p, so for an affine deformation
  // u_bar(p) = (S - I)(p - x_bar) exactly: zero to first order in strain times h, not zero.
  const Window surfaceWindow = gatherWindow(sampling, kTop, options.window);
  const DeformationDescriptor s = deformationDescriptor(surfaceWindow, sampling.points(), affine, 2);
  const int top = sampling.nearest(kTop);
  const Eigen::Vector3d expected = (s.S - Eigen::Matrix3d::Identity()) * (sampling.points().col(top) - s.xBar);
  EXPECT_LT((rigidFreeDisplacement(sampling.points(), affine, s.R, s.t).col(top) - expected).norm(), 1e-12);
  EXPECT_GT((s.xBar - kTop).norm(), 0.5 * options.window.scale);

  // With a localised indentation u_bar(p) keeps the part of the dent that is not a rigid motion: smaller
  // than the displacement itself, not zero. mu_0 (the q omega-weighted mean of u_bar) is zero to round-off.
  const Eigen::Matrix3Xd indented = deform(sampling.points(), syntheticModes()[0].second);
  const Window topWindow = gatherWindow(sampling, kTop, options.window);
  const DeformationDescriptor t = deformationDescriptor(topWindow, sampling.points(), indented, 2);
  const Eigen::Matrix3Xd topBar = rigidFreeDisplacement(sampling.points(), indented, t.R, t.t);
  const double uTop = (indented.col(top) - sampling.points().col(top)).norm();
  std::printf("indent: |u(p)| = %.3e, |u_bar(p)| = %.3e\n", uTop, topBar.col(top).norm());
  EXPECT_LT(topBar.col(top).norm(), 0.5 * uTop);
  Eigen::Matrix3Xd windowBar(3, topWindow.indices.size());
  for (std::size_t k = 0; k < topWindow.indices.size(); ++k) windowBar.col(k) = topBar.col(topWindow.indices[k]);
  const hermite::MomentList mu0 = fieldMoments(topWindow, windowBar, 0, 1);
  for (int c0 = 0; c0 < 3; ++c0) EXPECT_LT(std::abs(mu0.order(0, c0)[0]), 1e-12 * hermite::norm(t.mu));
}

TEST(DeformationDescriptor, Table1PropertiesOnCubeOfEdgeTwo) {
  const DescriptorEvaluator evaluator(cube(), cubeOptions());
  const auto modes = syntheticModes();
  const int count = static_cast<int>(modes.size());
  std::vector<ContactDescriptor> descriptors;
  for (const auto& mode : modes) descriptors.push_back(evaluator.evaluate(kTop, deform(cube().vertices, mode.second)));
  Eigen::MatrixXd d(count, count);
  for (int i = 0; i < count; ++i)
    for (int j = 0; j < count; ++j) d(i, j) = deformationDistance(descriptors[i].mu, descriptors[j].mu);
  std::printf("Table 1 analogue, d_u at the top centre (N = 2):\n");
  for (int i = 0; i < count; ++i) {
    std::printf("%-13s (%s)", modes[i].first.c_str(), toString(descriptors[i].frame.rule));
    for (int j = 0; j < count; ++j) std::printf(" %6.3f", d(i, j));
    std::printf("\n");
  }
  EXPECT_LT((d - d.transpose()).cwiseAbs().maxCoeff(), 1e-12) << "symmetric";
  EXPECT_LT(d.diagonal().cwiseAbs().maxCoeff(), 1e-12) << "zero diagonal";
  EXPECT_LE(d(6, 7), 1e-9) << "a rotated copy of a mode is the same mode";
  EXPECT_NEAR(d(0, 1), 2.0, 1e-9) << "pull is the opposite of indent";
  for (int i = 0; i < 7; ++i)
    for (int j = i + 1; j < 7; ++j) EXPECT_GT(d(i, j), 0.05) << modes[i].first << " vs " << modes[j].first;
  // An arbitrary rotation angle (the mesh is only 4-fold symmetric) stays close.
  const Eigen::Matrix3d Q = Eigen::AngleAxisd(0.52, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Mode poke = modes[6].second;
  const ContactDescriptor turned = evaluator.evaluate(
      kTop, deform(cube().vertices, [&](const Eigen::Vector3d& x) -> Eigen::Vector3d { return Eigen::Vector3d(Q * poke(Q.transpose() * x)); }));
  const double turnedDistance = deformationDistance(descriptors[6].mu, turned.mu);
  std::printf("poke rotated by 0.52 rad: d_u = %.3e\n", turnedDistance);
  EXPECT_LT(turnedDistance, 0.01);
}

TEST(DeformationDescriptor, InvariantUnderRandomRigidMotions) {
  std::mt19937 rng(29);
  const DescriptorOptions options = cubeOptions();
  const DescriptorEvaluator evaluator(cube(), options);
  const Eigen::Vector3d p(0.63, 0.31, 1.0);  // off the grid, near an edge: rho_1 defines b_x
  const auto modes = syntheticModes();
  std::vector<ContactDescriptor> reference;
  for (int m : {0, 2, 3}) reference.push_back(evaluator.evaluate(p, deform(cube().vertices, modes[m].second)));
  EXPECT_EQ(reference[0].frame.rule, FrameRule::SiteMoment);

  for (int trial = 0; trial < 3; ++trial) {
    const Eigen::Matrix3d Q = de_test::randomRotation(rng);
    const Eigen::Vector3d shift(trial, -1.0, 2.0 * trial);
    // (a) rigid motion of the deformed state only: mu unchanged.
    // (b) the whole configuration (rest mesh, contact, deformed state) moved: mu in frame B unchanged.
    mesh::TetMesh movedRest = cube();
    movedRest.vertices = (Q * cube().vertices).colwise() + shift;
    const DescriptorEvaluator movedEvaluator(movedRest, options);
    int k = 0;
    for (int m : {0, 2, 3}) {
      const Eigen::Matrix3Xd deformed = deform(cube().vertices, modes[m].second);
      const ContactDescriptor a = evaluator.evaluate(p, (Q * deformed).colwise() + shift);
      EXPECT_LE(deformationDistance(a.mu, reference[k].mu), 1e-9);
      EXPECT_LT((a.mu.values() - reference[k].mu.values()).cwiseAbs().maxCoeff(), 1e-12);
      const ContactDescriptor b = movedEvaluator.evaluate(Q * p + shift, (Q * deformed).colwise() + shift);
      EXPECT_LE(deformationDistance(b.mu, reference[k].mu), 1e-9);
      EXPECT_LE(siteDistance(b.rho, reference[k].rho), 1e-9);
      ++k;
    }
  }
}

TEST(DeformationDescriptor, FrameFallsBackToDeformationDirectionThenFixed) {
  const DescriptorEvaluator evaluator(cube(), cubeOptions());
  const auto modes = syntheticModes();
  const ContactDescriptor drag = evaluator.evaluate(kTop, deform(cube().vertices, modes[2].second));
  EXPECT_EQ(drag.frame.rule, FrameRule::DeformationDirection);
  EXPECT_GT(drag.frame.B.col(0).x(), 0.999) << "b_x follows the drag";
  const ContactDescriptor rest = evaluator.evaluate(kTop);
  EXPECT_EQ(rest.frame.rule, FrameRule::Fixed);
  for (const ContactDescriptor* c : {&drag, &rest}) {
    EXPECT_TRUE(c->frame.B.allFinite());
    EXPECT_LT((c->frame.B.transpose() * c->frame.B - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_NEAR(c->frame.B.determinant(), 1.0, 1e-12);
    EXPECT_GT(c->frame.B.col(2).z(), 0.999) << "b_z is the outward normal";
  }
  // A zero normal and zero moments still give a proper frame.
  const StampingFrame degenerate = stampingFrame(Eigen::Vector3d::Zero(), hermite::MomentList(0, 3));
  EXPECT_TRUE(degenerate.B.isApprox(Eigen::Matrix3d::Identity()));
  EXPECT_THROW(stampingFrame(Eigen::Vector3d(NAN, 0, 1), hermite::MomentList(0, 3)), InvalidInputError);
}

TEST(DeformationDescriptor, FlatSampleSetUsesNormalCompletion) {
  // Surface-only coarse state near a flat contact: the top-face vertices are coplanar.
  std::vector<int> topVertices;
  for (Eigen::Index v = 0; v < cube().vertices.cols(); ++v)
    if (cube().vertices(2, v) > 1.0 - 1e-12) topVertices.push_back(static_cast<int>(v));
  Eigen::Matrix3Xd rest(3, topVertices.size());
  for (std::size_t k = 0; k < topVertices.size(); ++k) rest.col(k) = cube().vertices.col(topVertices[k]);
  const PointSampling flat(rest, Eigen::VectorXd::Constant(rest.cols(), 0.01));
  WindowOptions options = cubeOptions().window;
  const Window window = gatherWindow(flat, kTop, options);
  const Eigen::Matrix3Xd deformed = deform(rest, syntheticModes()[4].second);
  const Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  EXPECT_THROW(deformationDescriptor(window, rest, deformed, 2), InvalidInputError) << "needs the normals";
  const DeformationDescriptor d = deformationDescriptor(window, rest, deformed, 2, &normal, &normal);
  EXPECT_TRUE(d.normalCompleted);
  EXPECT_TRUE(d.F.allFinite());
  EXPECT_TRUE(d.mu.values().allFinite());
  EXPECT_GT(hermite::norm(d.mu), 0.0);
}

TEST(DeformationDescriptor, BadInput) {
  const DescriptorEvaluator evaluator(cube(), cubeOptions());
  Eigen::Matrix3Xd deformed = cube().vertices;
  EXPECT_THROW(evaluator.evaluate(kTop, Eigen::Matrix3Xd(3, 5)), InvalidInputError);
  deformed(0, evaluator.sampling().nearest(kTop)) = NAN;
  EXPECT_THROW(evaluator.evaluate(kTop, deformed), InvalidInputError);
  const Window window = gatherWindow(evaluator.sampling(), kTop, cubeOptions().window);
  EXPECT_THROW(deformationDescriptor(window, cube().vertices, cube().vertices, 0), InvalidInputError);
  // d_u: both zero -> 0, one zero -> 1, NaN -> error.
  hermite::MomentList zero(1, 2, 3), some(1, 2, 3);
  some.values().setOnes();
  EXPECT_EQ(deformationDistance(zero, zero), 0.0);
  EXPECT_EQ(deformationDistance(zero, some), 1.0);
  EXPECT_EQ(deformationDistance(some, zero), 1.0);
  EXPECT_NEAR(deformationDistance(some, some), 0.0, 1e-15);
  hermite::MomentList tiny = some;
  tiny.values() *= 1e-200;  // no underflow to NaN
  EXPECT_NEAR(deformationDistance(tiny, some), 0.0, 1e-15);
  some.values()[0] = NAN;
  EXPECT_THROW(deformationDistance(zero, some), InvalidInputError);
  EXPECT_THROW(siteDistance(hermite::MomentList(0, 3), hermite::MomentList(0, 2)), InvalidInputError);
}

TEST(DeformationDescriptor, TheSameDeformationOnTwoMeshingsGivesTheSameMu) {
  // mu integrates the rigid-free displacement over the window's volume (eq. 11 with the volume quadrature),
  // so like rho it describes the shape and its deformation, not the mesh: the cube meshed with 16 and with 24
  // cells per edge (spacing h / 1.6 and h / 2.4) under the same displacement fields.
  const mesh::TetMesh coarse = de_test::uniformBox(Eigen::Vector3d(-1, -1, -1), Eigen::Vector3d(1, 1, 1), 16);
  const mesh::TetMesh fine = de_test::uniformBox(Eigen::Vector3d(-1, -1, -1), Eigen::Vector3d(1, 1, 1), 24);
  const DescriptorEvaluator onCoarse(coarse, cubeOptions()), onFine(fine, cubeOptions());
  for (const auto& [name, mode] : syntheticModes()) {
    const ContactDescriptor a = onCoarse.evaluate(kTop, deform(coarse.vertices, mode));
    const ContactDescriptor b = onFine.evaluate(kTop, deform(fine.vertices, mode));
    const double relative = (a.mu.values() - b.mu.values()).norm() / b.mu.values().norm();
    const double du = deformationDistance(a.mu, b.mu);
    std::printf("%-13s |mu_16 - mu_24| / |mu_24| = %.3e, d_u = %.3e\n", name.c_str(), relative, du);
    EXPECT_LT(relative, 0.05) << name;
    EXPECT_LT(du, 0.05) << name;
  }
}
