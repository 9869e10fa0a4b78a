#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <unistd.h>

#include "deformation_enrichment/acquisition/example_generation.hpp"
#include "deformation_enrichment/enrichment/stamp.hpp"
#include "deformation_enrichment/error.hpp"

using namespace deformation_enrichment;

namespace {

std::string writeTemp(const std::string& name, const std::string& text) {
  const std::string path = "/tmp/de_acq_" + std::to_string(::getpid()) + "_" + name;
  std::ofstream(path) << text;
  return path;
}

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

TEST(ExampleGeneration, PlanRoundTripAndErrors) {
  const auto plan = acquisition::defaultSlabPlan();
  EXPECT_GE(plan.size(), 8u);
  const std::string path = "/tmp/de_acq_" + std::to_string(::getpid()) + "_plan.csv";
  acquisition::writePlan(path, plan);
  const auto read = acquisition::readPlan(path);
  ASSERT_EQ(read.size(), plan.size());
  for (std::size_t i = 0; i < plan.size(); ++i) {
    EXPECT_EQ(read[i].point, plan[i].point);
    EXPECT_EQ(read[i].depth, plan[i].depth);
    EXPECT_EQ(read[i].drag, plan[i].drag);
  }
  EXPECT_THROW(acquisition::readPlan(writeTemp("a.csv", "0,0,0.02,0.003,0,0\n")), IoError);
  EXPECT_THROW(acquisition::readPlan(writeTemp("b.csv", "0,0,0.02,x,0,0,0\n")), IoError);
  EXPECT_THROW(acquisition::readPlan(writeTemp("c.csv", "0,0,0.02,nan,0,0,0\n")), IoError);
  EXPECT_THROW(acquisition::readPlan(writeTemp("d.csv", "0,0,0.02,-0.001,0,0,0\n")), IoError);
  EXPECT_THROW(acquisition::readPlan(writeTemp("e.csv", "# nothing\n\n")), IoError);
  EXPECT_THROW(acquisition::readPlan("/nonexistent/plan.csv"), IoError);
  EXPECT_EQ(acquisition::readPlan(writeTemp("f.csv", "# c\n 0, 0 ,0.02,0.003,0.001,0,0 \n")).size(), 1u);
}

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
  acquisition::SlabAcquisition acq(tiny());
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
  // One-example set at its own contact: the enriched state must be closer to the fine one near p.
  examples::ExampleSet set;
  set.metadata.scene = "slab";
  set.examples.push_back(ex);
  enrichment::ExampleBlenderOptions b;
  b.fitWidths = false;
  acq.enricher().setExamples(set, b);
  enrichment::EnrichmentResult result;
  acq.enricher().enrich(r.coarseOnFine, {acquisition::SlabAcquisition::contactOf(e)}, result);
  ASSERT_FALSE(result.enrichment.vertices.empty());
  Eigen::Matrix3Xd enriched = r.coarseOnFine;
  acq.enricher().apply(result, enriched);
  double coarseSq = 0.0, enrichedSq = 0.0;
  const double inner = 0.5 * ex.stampRadius;
  for (int v : result.enrichment.vertices) {
    if ((acq.fineSurface().vertices.col(v) - ex.contact).norm() > inner) continue;
    coarseSq += (r.coarseOnFine.col(v) - r.fine.col(v)).squaredNorm();
    enrichedSq += (enriched.col(v) - r.fine.col(v)).squaredNorm();
  }
  EXPECT_GT(coarseSq, 0.0);
  EXPECT_LT(enrichedSq, 0.1 * coarseSq);
}
