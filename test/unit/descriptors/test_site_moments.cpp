#include <gtest/gtest.h>

#include <cstdio>

#include "descriptor_test_support.hpp"
#include "deformation_enrichment/descriptors/descriptor_distance.hpp"
#include "deformation_enrichment/descriptors/descriptor_evaluator.hpp"
#include "deformation_enrichment/descriptors/moment_window.hpp"
#include "deformation_enrichment/descriptors/site_descriptor_table.hpp"
#include "deformation_enrichment/error.hpp"

using namespace deformation_enrichment;
using namespace deformation_enrichment::descriptors;
using de_test::boxMoments;
using de_test::relativeError;

namespace {
WindowOptions windowOptions(double h, Quadrature quadrature) {
  WindowOptions options;
  options.scale = h;
  options.quadrature = quadrature;
  return options;
}

// A graded mesh of the same box: spacing grows geometrically (ratio ~1.4 from one side to the other),
// so the vertex density varies by an order of magnitude across the window.
mesh::TetMesh gradedBox(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, int cells) {
  Eigen::VectorXd axes[3];
  for (int axis = 0; axis < 3; ++axis) {
    axes[axis].resize(cells + 1);
    const double ratio = 1.08;
    double total = 0.0, step = 1.0;
    for (int k = 0; k < cells; ++k, step *= ratio) total += step;
    axes[axis][0] = lo[axis];
    step = 1.0;
    for (int k = 0; k < cells; ++k, step *= ratio) axes[axis][k + 1] = axes[axis][k] + (hi[axis] - lo[axis]) * step / total;
    axes[axis][cells] = hi[axis];
  }
  return mesh::gridTetMesh(axes[0], axes[1], axes[2]);
}
}  // namespace

TEST(SiteMoments, VolumeQuadratureConvergesToExactBoxMoments) {
  const Eigen::Vector3d lo(-1, -1, -1), hi(1, 1, 1);
  const Eigen::Vector3d p(0.3, -0.2, 1.0);  // on the top face
  const double h = 0.4;
  const hermite::MomentList exact = boxMoments(lo, hi, p, h, 3);
  double previous = 1e300;
  for (int cellsPerUnit : {5, 10, 20}) {
    const PointSampling sampling = PointSampling::fromTetMesh(de_test::uniformBox(lo, hi, cellsPerUnit));
    const double error =
        relativeError(densityMoments(gatherWindow(sampling, p, windowOptions(h, Quadrature::Volume)), 0, 3), exact);
    std::printf("volume quadrature, spacing h/%.1f: relative error %.3e\n", h * cellsPerUnit, error);
    EXPECT_LT(error, 0.7 * previous) << "error must shrink with refinement";
    previous = error;
  }
  // Vertex lumping is second order: spacing 0.05 = h/8 -> error of order (1/8)^2 times a constant < 1.
  EXPECT_LT(previous, 0.01);
}

TEST(SiteMoments, MeshIndependenceVolumeBeatsAverage) {
  // One shape, three meshes: uniform coarse, uniform fine, graded. Compare each descriptor with the
  // fine uniform one (and the volume one with the exact moments too).
  const Eigen::Vector3d lo(-1, -1, -1), hi(1, 1, 1);
  const double h = 0.4;
  const mesh::TetMesh meshes[3] = {de_test::uniformBox(lo, hi, 8), de_test::uniformBox(lo, hi, 16),
                                   gradedBox(lo, hi, 24)};
  const char* names[3] = {"uniform 1/8", "uniform 1/16", "graded 24 cells"};
  std::vector<PointSampling> samplings;
  for (const auto& m : meshes) samplings.push_back(PointSampling::fromTetMesh(m));
  const Eigen::Vector3d points[3] = {Eigen::Vector3d(0.2, 0.1, 1.0), Eigen::Vector3d(1.0, 1.0, 1.0),
                                     Eigen::Vector3d(-0.5, 1.0, 0.0)};
  for (const Eigen::Vector3d& p : points) {
    const hermite::MomentList exact = boxMoments(lo, hi, p, h, 3);
    double worst[2] = {0.0, 0.0};
    for (int q = 0; q < 2; ++q) {
      const Quadrature quadrature = q == 0 ? Quadrature::Volume : Quadrature::Average;
      const hermite::MomentList reference =
          densityMoments(gatherWindow(samplings[1], p, windowOptions(h, quadrature)), 0, 3);
      for (int k : {0, 2}) {
        const hermite::MomentList other =
            densityMoments(gatherWindow(samplings[k], p, windowOptions(h, quadrature)), 0, 3);
        const double disagreement = relativeError(other, reference);
        std::printf("p=(%.1f %.1f %.1f) %-7s %-15s vs uniform 1/16: %.3e\n", p.x(), p.y(), p.z(),
                    toString(quadrature).c_str(), names[k], disagreement);
        worst[q] = std::max(worst[q], disagreement);
      }
      if (quadrature == Quadrature::Volume) {
        EXPECT_LT(relativeError(reference, exact), 0.02);  // lumping error at dx = h/6.4, worst at corners
      }
    }
    // Tolerance: lumping error O((dx/h)^2) with dx/h <= 0.31 on the coarse mesh gives a few percent at
    // most; the averaging quadrature is biased by the vertex density itself and must be clearly worse.
    EXPECT_LT(worst[0], 0.03);
    EXPECT_GT(worst[1], 3.0 * worst[0]) << "average quadrature should be clearly less mesh independent";
  }
}

TEST(SiteMoments, RigidMotionRotatesMomentsAndKeepsFrameDescriptors) {
  std::mt19937 rng(17);
  const mesh::TetMesh box = de_test::uniformBox(Eigen::Vector3d(-1, -0.5, -0.3), Eigen::Vector3d(1, 0.5, 0.3), 10);
  mesh::TetMesh moved = box;
  const Eigen::Matrix3d Q = de_test::randomRotation(rng);
  const Eigen::Vector3d shift(0.3, -2.0, 5.0);
  moved.vertices = (Q * box.vertices).colwise() + shift;
  DescriptorOptions options;
  options.window.scale = 0.25;
  const DescriptorEvaluator original(box, options), transformed(moved, options);
  // Surface points with a clear tangential rho_1 (near edges / corners). They sit off the grid: a sample at
  // exactly the cut-off distance would be kept or dropped by round-off after the motion, a jump of up to
  // omega(4)/omega(0) = 3.4e-4 of one sample's weight; invariance holds to round-off otherwise.
  const Eigen::Vector3d points[4] = {Eigen::Vector3d(0.8, 0.5, 0.12), Eigen::Vector3d(-0.63, -0.5, -0.27),
                                     Eigen::Vector3d(1.0, 0.13, 0.27), Eigen::Vector3d(0.43, -0.5, 0.06)};
  std::vector<ContactDescriptor> a, b;
  for (const Eigen::Vector3d& p : points) {
    a.push_back(original.evaluate(p));
    b.push_back(transformed.evaluate(Q * p + shift));
    // Appendix B: moments of the moved mesh = rotated moments.
    EXPECT_LT((a.back().rhoWorld.transformed(Q).values() - b.back().rhoWorld.values()).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_EQ(a.back().frame.rule, FrameRule::SiteMoment);
    EXPECT_LT((Q * a.back().frame.B - b.back().frame.B).cwiseAbs().maxCoeff(), 1e-9);
    EXPECT_LE(siteDistance(a.back().rho, b.back().rho), 1e-9) << "d_rho must be invariant";
  }
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      EXPECT_NEAR(siteDistance(a[i].rho, a[j].rho), siteDistance(b[i].rho, b[j].rho), 1e-9);
  EXPECT_GT(siteDistance(a[0].rho, a[1].rho), 1e-3) << "different sites must be apart";
}

TEST(SiteMoments, BadInputGivesTypedErrorsOrDefinedResults) {
  EXPECT_THROW(PointSampling(Eigen::Matrix3Xd(3, 0), Eigen::VectorXd(0)), InvalidInputError);
  Eigen::Matrix3Xd points = Eigen::Matrix3Xd::Random(3, 5);
  EXPECT_THROW(PointSampling(points, Eigen::VectorXd::Ones(4)), InvalidInputError);
  EXPECT_THROW(PointSampling(points, -Eigen::VectorXd::Ones(5)), InvalidInputError);
  points(1, 2) = NAN;
  EXPECT_THROW(PointSampling(points, Eigen::VectorXd::Ones(5)), InvalidInputError);

  mesh::TetMesh degenerate = de_test::uniformBox(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(), 2);
  degenerate.vertices.col(degenerate.tets(3, 0)) = degenerate.vertices.col(degenerate.tets(0, 0));
  EXPECT_THROW(PointSampling::fromTetMesh(degenerate), InvalidInputError);

  const PointSampling sampling =
      PointSampling::fromTetMesh(de_test::uniformBox(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(), 4));
  EXPECT_THROW(gatherWindow(sampling, Eigen::Vector3d(NAN, 0, 0), WindowOptions{}), InvalidInputError);
  WindowOptions bad;
  bad.scale = 0.0;
  EXPECT_THROW(gatherWindow(sampling, Eigen::Vector3d::Zero(), bad), InvalidInputError);
  bad.scale = 0.1;
  bad.cutoff = -1.0;
  EXPECT_THROW(gatherWindow(sampling, Eigen::Vector3d::Zero(), bad), InvalidInputError);
  EXPECT_THROW(parseQuadrature("simpson"), InvalidInputError);

  // Far from the mesh: every weight is zero -> zero moments for both quadratures (no material), no NaN.
  for (Quadrature quadrature : {Quadrature::Volume, Quadrature::Average}) {
    WindowOptions options;
    options.scale = 0.1;
    options.quadrature = quadrature;
    const Window window = gatherWindow(sampling, Eigen::Vector3d(50, 0, 0), options);
    EXPECT_TRUE(window.empty());
    const hermite::MomentList rho = densityMoments(window, 0, 3);
    EXPECT_TRUE(rho.values().allFinite());
    EXPECT_EQ(rho.values().cwiseAbs().maxCoeff(), 0.0);
  }
  DescriptorOptions options;
  options.window.scale = 0.1;
  const DescriptorEvaluator evaluator(de_test::uniformBox(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(), 4), options);
  const ContactDescriptor far = evaluator.evaluate(Eigen::Vector3d(50, 0, 0));
  EXPECT_TRUE(far.rho.values().allFinite());
  EXPECT_TRUE(far.frame.B.allFinite());
  EXPECT_NEAR(far.frame.B.determinant(), 1.0, 1e-12);
  EXPECT_THROW(evaluator.evaluate(Eigen::Vector3d(50, 0, 0), evaluator.sampling().points()), InvalidInputError);
  options.siteOrder = 7;
  EXPECT_THROW(DescriptorEvaluator(de_test::uniformBox(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(), 2), options),
               InvalidInputError);
}

TEST(SiteMoments, KdTreeAndBruteForceAgree) {
  const PointSampling sampling =
      PointSampling::fromTetMesh(de_test::uniformBox(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(), 12));
  WindowOptions kd, brute;
  kd.scale = brute.scale = 0.1;
  brute.search = NeighbourSearch::BruteForce;
  const Eigen::Vector3d p(0.5, 0.3, 1.0);
  const Window a = gatherWindow(sampling, p, kd), b = gatherWindow(sampling, p, brute);
  EXPECT_EQ(a.indices.size(), b.indices.size());
  EXPECT_NEAR(hermite::norm(densityMoments(a, 0, 4)), hermite::norm(densityMoments(b, 0, 4)), 1e-13);
}

TEST(SiteMoments, TableLooksUpTheNearestVertexDescriptor) {
  DescriptorOptions options;
  options.window.scale = 0.2;
  const DescriptorEvaluator evaluator(de_test::uniformBox(Eigen::Vector3d(-1, -1, -1), Eigen::Vector3d(1, 1, 1), 5), options);
  const SiteDescriptorTable table(evaluator);
  ASSERT_EQ(table.size(), evaluator.surface().numVertices());
  const Eigen::Index v = 17;
  const Eigen::Vector3d vertex = evaluator.surface().vertices.col(v);
  const ContactDescriptor direct = evaluator.evaluate(vertex);
  EXPECT_EQ(table.atVertex(v).rho.values(), direct.rho.values());
  EXPECT_EQ(table.nearest(vertex + Eigen::Vector3d(0.01, -0.01, 0.01)).rho.values(), direct.rho.values());
  EXPECT_THROW(table.atVertex(table.size()), InvalidInputError);
  EXPECT_THROW(table.nearest(Eigen::Vector3d(NAN, 0, 0)), InvalidInputError);
}
