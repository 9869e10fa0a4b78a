#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <limits>
#include <unistd.h>

#include "deformation_enrichment/acquisition/held_out_evaluation.hpp"
#include "deformation_enrichment/examples/example_set_io.hpp"
#include "deformation_enrichment/enrichment/stamp.hpp"
#include "deformation_enrichment/error.hpp"

using namespace deformation_enrichment;

namespace {

acquisition::SlabAcquisitionOptions tiny() {
  acquisition::SlabAcquisitionOptions o;
  o.coarse = scenes::Layering{Eigen::Vector3i(6, 6, 1), 0.001, 1};
  o.fine = scenes::Layering{Eigen::Vector3i(12, 12, 2), 0.001, 1};
  o.indentSteps = 1;
  o.dragSteps = 1;
  o.stampResolution = 16;
  o.enricher.descriptors.window.scale = 0.008;
  o.enricher.sampleSpacing = 0.004;
  return o;
}

}  // namespace

TEST(ExampleGeneration, IdenticalCoarseAndFineGiveAZeroStamp) {
  // Same resolution for both: the embedding is exact and d = fine - coarse must vanish.
  auto o = tiny();
  o.fine = o.coarse;
  acquisition::SlabAcquisition acq(o);
  acquisition::PlanEntry e;
  e.point = Eigen::Vector3d(0.0, 0.0, 0.02);
  e.depth = 0.002;
  e.drag = Eigen::Vector3d(0.003, 0.0, 0.0);
  const auto r = acq.simulate(e);
  EXPECT_TRUE(r.converged) << r.message;
  EXPECT_LT((r.fine - r.coarseOnFine).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_GT((r.fine - acq.fineSurface().vertices).cwiseAbs().maxCoeff(), 1e-3);  // it did move
  const examples::Example ex = acq.makeExample(e, r);
  double maxStamp = 0.0;
  for (int j = 0; j < ex.stamp.rows; ++j)
    for (int k = 0; k < ex.stamp.cols; ++k) maxStamp = std::max(maxStamp, cv::norm(ex.stamp.at<cv::Vec3f>(j, k)));
  EXPECT_LT(maxStamp, 1e-8);
}

TEST(ExampleGeneration, FineDetailIsCapturedAndReproducedByTheEnricher) {
  auto o = tiny();
  o.enricher.rimBand = 0.0;  // the rim fade alone costs ~0.26 of the coarse error here: test the pipeline
  acquisition::SlabAcquisition acq(o);
  acquisition::PlanEntry e;
  e.point = Eigen::Vector3d(0.002, -0.001, 0.02);
  e.depth = 0.003;
  const auto r = acq.simulate(e);
  EXPECT_TRUE(r.converged) << r.message;
  const examples::Example ex = acq.makeExample(e, r);
  EXPECT_NO_THROW(examples::validateExample(ex));
  EXPECT_EQ(ex.stamp.rows, 16);
  EXPECT_DOUBLE_EQ(ex.stampRadius, acq.options().enricher.stampRadius);
  EXPECT_NEAR(ex.frame.col(2).z(), 1.0, 1e-6);
  const double dMax = (r.fine - r.coarseOnFine).cwiseAbs().maxCoeff();
  EXPECT_GT(dMax, 1e-5);  // coarse and fine differ
  // One-example set at its own contact, scored like held-out data: the enriched state must be much closer
  // to the fine one than the coarse state is.
  examples::ExampleSet set;
  set.metadata.scene = "slab";
  set.examples.push_back(ex);
  enrichment::ExampleBlenderOptions b;
  b.fitWidths = false;
  acq.enricher().setExamples(set, b);
  const acquisition::HeldOutScore score = acquisition::scoreHeldOut(acq.enricher(), {{e, r}}, 3);
  ASSERT_EQ(score.contacts.size(), 1u);
  EXPECT_GT(score.contacts[0].vertices, 10);
  EXPECT_GT(score.coarseRms, 1e-5);
  EXPECT_LT(score.ratio(), 0.15);  // what is left: 16-node stamp discretisation
  EXPECT_GT(score.secondsPerFrame, 0.0);
}

TEST(ExampleGeneration, AcquiredSetResumesWithoutRecomputing) {
  auto o = tiny();
  acquisition::SlabAcquisition acq(o);
  std::vector<acquisition::PlanEntry> plan(2);
  plan[0].point = Eigen::Vector3d(0.0, 0.0, 0.02);
  plan[0].depth = 0.002;
  plan[1].point = Eigen::Vector3d(0.01, 0.005, 0.02);
  plan[1].depth = 0.003;
  plan[1].drag = Eigen::Vector3d(0.002, 0.0, 0.0);
  const std::string dir = "/tmp/de_acq_" + std::to_string(::getpid()) + "_set";
  std::filesystem::remove_all(dir);
  const examples::ExampleSet first = acq.acquireSet({plan[0]}, dir);
  ASSERT_EQ(first.examples.size(), 1u);
  std::ostringstream log;
  const examples::ExampleSet both = acq.acquireSet(plan, dir, &log);
  ASSERT_EQ(both.examples.size(), 2u);
  EXPECT_NE(log.str().find("[1/2] already acquired"), std::string::npos) << log.str();
  EXPECT_EQ(cv::norm(both.examples[0].stamp, first.examples[0].stamp, cv::NORM_INF), 0.0);
  EXPECT_EQ(examples::loadExampleSet(dir).examples.size(), 2u);
  // Another stamp resolution is another set: nothing is reused.
  o.stampResolution = 8;
  std::ostringstream again;
  acquisition::SlabAcquisition(o).acquireSet({plan[0]}, dir, &again);
  EXPECT_EQ(again.str().find("already acquired"), std::string::npos);
  std::filesystem::remove_all(dir);
}

TEST(ExampleGeneration, CoarsePathEndsInTheSimulatedCoarseState) {
  const auto o = tiny();
  const acquisition::SlabAcquisition acq(o);
  acquisition::PlanEntry e;
  e.point = Eigen::Vector3d(0.004, 0.003, 0.02);
  e.depth = 0.002;
  e.drag = Eigen::Vector3d(0.0, 0.002, 0.0);
  std::string message;
  const auto path = acq.coarsePath(e, o.indentSteps, o.dragSteps, &message);
  ASSERT_EQ(path.size(), static_cast<std::size_t>(1 + o.indentSteps + o.dragSteps));
  EXPECT_TRUE(message.empty()) << message;
  EXPECT_EQ(path.front(), acq.fineSurface().vertices);
  EXPECT_LT((path.back() - acq.simulate(e).coarseOnFine).cwiseAbs().maxCoeff(), 1e-9);
  // The surface under the tool goes down monotonically while indenting.
  Eigen::Index under = 0;
  (acq.fineSurface().vertices.colwise() - e.point).colwise().squaredNorm().minCoeff(&under);
  for (int step = 1; step <= o.indentSteps; ++step)
    EXPECT_LT(path[static_cast<std::size_t>(step)](2, under), path[static_cast<std::size_t>(step - 1)](2, under) - 1e-4);
  e.drag.setZero();
  EXPECT_EQ(acq.coarsePath(e, 3, 5).size(), 4u);  // no drag, no drag steps
  EXPECT_THROW(acq.coarsePath(e, 0, 1), InvalidInputError);
}

TEST(ExampleGeneration, RejectsABadCoarseSkinModulus) {
  for (double young : {-1.0, std::nan(""), std::numeric_limits<double>::infinity()}) {
    auto o = tiny();
    o.coarseSkinYoung = young;
    EXPECT_THROW(acquisition::SlabAcquisition{o}, InvalidInputError) << young;
  }
}
