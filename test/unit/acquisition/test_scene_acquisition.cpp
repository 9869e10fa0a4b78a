#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <sstream>
#include <filesystem>
#include <limits>
#include <unistd.h>

#include "deformation_enrichment/acquisition/fine_convergence.hpp"
#include "deformation_enrichment/acquisition/held_out_evaluation.hpp"
#include "deformation_enrichment/acquisition/plan_generation.hpp"
#include "deformation_enrichment/examples/example_set_io.hpp"
#include "deformation_enrichment/enrichment/stamp.hpp"
#include "deformation_enrichment/error.hpp"
#include "tiny_slab.hpp"

using namespace deformation_enrichment;

TEST(SceneAcquisition, IdenticalCoarseAndFineGiveAZeroStamp) {
  // Same resolution for both: the embedding is exact and d = fine - coarse must vanish.
  auto o = de_test::tinySlab();
  o.procedural->fineCells = o.procedural->coarseCells;
  o.procedural->fineSkinLayers = o.procedural->coarseSkinLayers;
  acquisition::SceneAcquisition acq(o);
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

TEST(SceneAcquisition, FineDetailIsCapturedAndReproducedByTheEnricher) {
  acquisition::SceneAcquisition acq(de_test::tinySlab());
  acquisition::PlanEntry e;
  e.point = Eigen::Vector3d(0.002, -0.001, 0.02);
  e.depth = 0.003;
  const auto r = acq.simulate(e);
  EXPECT_TRUE(r.converged) << r.message;
  const examples::Example ex = acq.makeExample(e, r);
  EXPECT_NO_THROW(examples::validateExample(ex));
  EXPECT_EQ(ex.stampLayers, 9);  // the default volume stamp: 9 layers of 16 x 16 nodes
  EXPECT_EQ(ex.stamp.rows, 16 * 9);
  EXPECT_EQ(ex.stamp.cols, 16);
  EXPECT_DOUBLE_EQ(ex.stampRadius, acq.scene().stamp.radius);
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
  enrichment::ContactEnricherOptions options = acquisition::enricherOptions(acq.scene());
  options.rimBand = 0.0;  // the rim fade alone costs ~0.26 of the coarse error here: test the pipeline
  enrichment::ContactEnricher enricher(acq.fineSurface(), options);
  enricher.setExamples(set, b);
  const std::vector<acquisition::HeldOutCase> cases = acquisition::simulateHeldOut(acq, {e});
  ASSERT_EQ(cases.size(), 1u);
  EXPECT_EQ(cv::norm(cases[0].ownStamp, ex.stamp, cv::NORM_INF), 0.0);  // the same interaction, the same stamp
  const acquisition::HeldOutScore score = acquisition::scoreHeldOut(enricher, cases, 3, acquisition::Bounds::Compute);
  ASSERT_EQ(score.contacts.size(), 1u);
  const acquisition::ContactScore& c = score.contacts[0];
  EXPECT_GT(c.vertices, 10);
  EXPECT_GT(score.coarseRms, 1e-5);
  EXPECT_LT(score.ratio(), 0.15);  // what is left: 16-node stamp discretisation
  EXPECT_DOUBLE_EQ(score.meanRatio(), score.ratio());  // one contact
  EXPECT_DOUBLE_EQ(score.worstRatio(), score.ratio());
  EXPECT_GT(score.secondsPerFrame, 0.0);
  // The oracle is the best multiple of the one stamp: never worse than the blend's multiple or the stamp itself,
  // and here (the set's example is the case's own) the stamp itself is within the blend's scale of it.
  EXPECT_LE(c.oracleRms, c.enrichedRms * (1 + 1e-9));
  EXPECT_LE(c.oracleRms, c.ownStampRms * (1 + 1e-9));
  EXPECT_GT(c.oracleRms, 0.0);
  EXPECT_LT(score.meanOwnStampRatio(), 0.15);
}

TEST(SceneAcquisition, HeldOutScoresDependNeitherOnRepetitionsNorOnTheBounds) {
  // The bounds place the set's own stamps; the enrichment of the next case must not write into them.
  acquisition::SceneAcquisition acq(de_test::tinySlab());
  std::vector<acquisition::PlanEntry> plan(2), held(2);
  plan[0].point = Eigen::Vector3d(0.0, 0.0, 0.02), plan[0].depth = 0.003;
  plan[1].point = Eigen::Vector3d(0.012, 0.004, 0.02), plan[1].depth = 0.002, plan[1].drag = Eigen::Vector3d(0.003, 0.0, 0.0);
  held[0].point = Eigen::Vector3d(0.004, 0.002, 0.02), held[0].depth = 0.0025;
  held[1].point = Eigen::Vector3d(0.008, -0.003, 0.02), held[1].depth = 0.003;
  examples::ExampleSet set;
  set.metadata.scene = "slab";
  for (const auto& e : plan) set.examples.push_back(acq.makeExample(e, acq.simulate(e)));
  std::vector<cv::Mat> stamps;
  for (const auto& e : set.examples) stamps.push_back(e.stamp.clone());
  enrichment::ContactEnricher enricher(acq.fineSurface(), acquisition::enricherOptions(acq.scene()));
  enricher.setExamples(set, enrichment::ExampleBlenderOptions());
  const std::vector<acquisition::HeldOutCase> cases = acquisition::simulateHeldOut(acq, held);
  const double plain = acquisition::scoreHeldOut(enricher, cases, 1).meanRatio();
  EXPECT_EQ(acquisition::scoreHeldOut(enricher, cases, 3, acquisition::Bounds::Compute).meanRatio(), plain);
  EXPECT_EQ(acquisition::scoreHeldOut(enricher, cases, 1).meanRatio(), plain);
  for (std::size_t i = 0; i < stamps.size(); ++i) EXPECT_EQ(cv::norm(enricher.blender()->stamps()[i], stamps[i], cv::NORM_INF), 0.0);
}

TEST(SceneAcquisition, GainGivenTheTruthIsWhatRescoringAtThatGainGives) {
  // The best factor on the detail, from one scoring, against scoring again with the stamp gain scaled by it.
  acquisition::SceneAcquisition acq(de_test::tinySlab());
  std::vector<acquisition::PlanEntry> plan(2), held(2);
  plan[0].point = Eigen::Vector3d(0.0, 0.0, 0.02), plan[0].depth = 0.003;
  plan[1].point = Eigen::Vector3d(0.012, 0.004, 0.02), plan[1].depth = 0.002;
  held[0].point = Eigen::Vector3d(0.004, 0.002, 0.02), held[0].depth = 0.0025;
  held[1].point = Eigen::Vector3d(0.008, -0.003, 0.02), held[1].depth = 0.0015;
  examples::ExampleSet set;
  set.metadata.scene = "slab";
  for (const auto& e : plan) set.examples.push_back(acq.makeExample(e, acq.simulate(e)));
  enrichment::ContactEnricher enricher(acq.fineSurface(), acquisition::enricherOptions(acq.scene()));
  enricher.setExamples(set, enrichment::ExampleBlenderOptions());
  enricher.setDetailGain({0.4, 0.0});  // far from the best: the factor must bring it back
  const std::vector<acquisition::HeldOutCase> cases = acquisition::simulateHeldOut(acq, held);
  const acquisition::HeldOutScore score = acquisition::scoreHeldOut(enricher, cases, 1);
  for (const acquisition::ContactScore& c : score.contacts) EXPECT_NEAR(c.ratioAtGain(1.0), c.ratio(), 1e-9);
  const double g = score.bestGain();
  ASSERT_GT(g, 1.0);
  const auto squares = [&](double factor) {
    double sum = 0.0;
    for (const acquisition::ContactScore& c : score.contacts) sum += c.ratioAtGain(factor) * c.ratioAtGain(factor);
    return sum;
  };
  EXPECT_LT(squares(g), squares(g * 0.9));
  EXPECT_LT(squares(g), squares(g * 1.1));
  EXPECT_LT(score.meanRatioAtGain(g), score.meanRatio());
  enricher.setDetailGain({0.4 * g, 0.0});
  const acquisition::HeldOutScore rescored = acquisition::scoreHeldOut(enricher, cases, 1);
  // Within 1e-7, not to the last bits: stamps are blended in single precision (CV_32FC3), so the detail is
  // linear in the gain only to float round-off.
  for (std::size_t i = 0; i < cases.size(); ++i) EXPECT_NEAR(score.contacts[i].ratioAtGain(g), rescored.contacts[i].ratio(), 1e-7);
  EXPECT_NEAR(score.meanRatioAtGain(g), rescored.meanRatio(), 1e-7);
  EXPECT_NEAR(score.worstRatioAtGain(g), rescored.worstRatio(), 1e-7);
  EXPECT_NEAR(rescored.bestGain(), 1.0, 1e-6);
}

TEST(SceneAcquisition, GainGivenTheTruthIsNeverNegative) {
  // Detail that points away from the truth: the best admissible stamp gain is none, and its ratio 1.
  acquisition::HeldOutScore score;
  score.contacts.resize(2);
  for (acquisition::ContactScore& c : score.contacts) c.coarseRms = 1e-3, c.detailAlong = -0.2, c.detailSize = 0.5;
  EXPECT_EQ(score.contacts[0].bestGain(), 0.0);
  EXPECT_EQ(score.bestGain(), 0.0);
  EXPECT_EQ(score.meanRatioAtGain(score.bestGain()), 1.0);
  score.contacts[1].detailAlong = 0.6;  // together they point towards it: (0.6 - 0.2) / (0.5 + 0.5)
  EXPECT_DOUBLE_EQ(score.bestGain(), 0.4);
  EXPECT_DOUBLE_EQ(score.contacts[1].bestGain(), 1.2);
  EXPECT_EQ(acquisition::HeldOutScore().bestGain(), 0.0);  // no contact, no detail
}

TEST(SceneAcquisition, AcquiredSetResumesWithoutRecomputing) {
  auto o = de_test::tinySlab();
  acquisition::SceneAcquisition acq(o);
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
  EXPECT_NE(log.str().find("[1/2] plan line 1 already acquired"), std::string::npos) << log.str();
  EXPECT_EQ(cv::norm(both.examples[0].stamp, first.examples[0].stamp, cv::NORM_INF), 0.0);
  const examples::ExampleSet loaded = examples::loadExampleSet(dir);
  ASSERT_EQ(loaded.examples.size(), 2u);
  EXPECT_EQ(loaded.examples[1].planLine, 1);
  // The provenance is the scene, typed: it reads back equal.
  ASSERT_TRUE(loaded.metadata.provenance);
  EXPECT_EQ(scene_file::sceneYaml(loaded.metadata.provenance->scene), scene_file::sceneYaml(o));
  // Another stamp resolution is another set: nothing is reused.
  o.stamp.resolution = 8;
  std::ostringstream again;
  acquisition::SceneAcquisition(o).acquireSet({plan[0]}, dir, &again);
  EXPECT_EQ(again.str().find("already acquired"), std::string::npos);
  std::filesystem::remove_all(dir);
}

TEST(SceneAcquisition, SurfacePathsEndInTheSimulatedCoarseAndFineStates) {
  const auto o = de_test::tinySlab();
  const acquisition::SceneAcquisition acq(o);
  using Resolution = acquisition::SceneAcquisition::Resolution;
  acquisition::PlanEntry e;
  e.point = Eigen::Vector3d(0.004, 0.003, 0.02);
  e.depth = 0.002;
  e.drag = Eigen::Vector3d(0.0, 0.002, 0.0);
  std::string message;
  const auto coarse = acq.surfacePath(Resolution::Coarse, e, o.solve.indentSteps, o.solve.dragSteps, &message);
  EXPECT_TRUE(message.empty()) << message;
  const auto fine = acq.surfacePath(Resolution::Fine, e, o.solve.indentSteps, o.solve.dragSteps, &message);
  EXPECT_TRUE(message.empty()) << message;
  for (const auto* path : {&coarse, &fine}) {
    ASSERT_EQ(path->size(), static_cast<std::size_t>(1 + o.solve.indentSteps + o.solve.dragSteps));
    EXPECT_EQ(path->front(), acq.fineSurface().vertices);
  }
  const acquisition::InteractionResult simulated = acq.simulate(e);
  EXPECT_LT((coarse.back() - simulated.coarseOnFine).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LT((fine.back() - simulated.fine).cwiseAbs().maxCoeff(), 1e-9);
  // The two models differ (else the fine truth beside the enrichment would show nothing), and the surface
  // under the tool goes down monotonically while indenting in both.
  EXPECT_GT((fine.back() - coarse.back()).cwiseAbs().maxCoeff(), 1e-5);
  Eigen::Index under = 0;
  (acq.fineSurface().vertices.colwise() - e.point).colwise().squaredNorm().minCoeff(&under);
  for (const auto* path : {&coarse, &fine})
    for (int step = 1; step <= o.solve.indentSteps; ++step)
      EXPECT_LT((*path)[static_cast<std::size_t>(step)](2, under), (*path)[static_cast<std::size_t>(step - 1)](2, under) - 1e-4);
  e.drag.setZero();
  EXPECT_EQ(acq.surfacePath(Resolution::Fine, e, 3, 5).size(), 4u);  // no drag, no drag steps
  EXPECT_THROW(acq.surfacePath(Resolution::Coarse, e, 0, 1), InvalidInputError);
}

TEST(SceneAcquisition, PlanPointsAreProjectedOntoTheSurfaceAndBadOnesRefusedBeforeWriting) {
  const acquisition::SceneAcquisition acq(de_test::tinySlab());
  acquisition::PlanEntry e;
  e.point = Eigen::Vector3d(0.004, 0.003, 0.025);  // 5 mm above the top
  e.depth = 0.002;
  e.drag = Eigen::Vector3d(0.002, 0.0, 0.001);
  const acquisition::ToolPath path = acq.toolPath(e);
  EXPECT_LT((path.contact - Eigen::Vector3d(0.004, 0.003, 0.02)).norm(), 1e-12);
  EXPECT_LT((path.inward + Eigen::Vector3d::UnitZ()).norm(), 1e-12);
  EXPECT_LT((path.drag - Eigen::Vector3d(0.002, 0.0, 0.0)).norm(), 1e-12);  // the tangential part only
  // Farther than the stamp radius from the surface, or on the held bottom: refused, nothing written.
  const std::string dir = "/tmp/de_acq_" + std::to_string(::getpid()) + "_refused";
  std::filesystem::remove_all(dir);
  acquisition::PlanEntry far = e, bottom = e;
  far.point.z() = 0.2;
  bottom.point.z() = -0.001;
  for (const auto& bad : {far, bottom}) {
    EXPECT_THROW(acq.toolPath(bad), InvalidInputError);
    acquisition::SceneAcquisition writer(de_test::tinySlab());
    EXPECT_THROW(writer.acquireSet({e, bad}, dir), InvalidInputError);
    EXPECT_FALSE(std::filesystem::exists(dir)) << "nothing may be written for a bad plan";
  }
}

TEST(SceneAcquisition, ShardsMergeIntoTheSingleRunsSet) {
  acquisition::SceneAcquisition acq(de_test::tinySlab());
  std::vector<acquisition::PlanEntry> plan(3);
  for (int k = 0; k < 3; ++k) {
    plan[k].point = Eigen::Vector3d(-0.01 + 0.01 * k, 0.004, 0.02);
    plan[k].depth = 0.002;
  }
  const std::string base = "/tmp/de_acq_" + std::to_string(::getpid());
  for (const char* d : {"_one", "_s1", "_s2", "_merged"}) std::filesystem::remove_all(base + d);
  acq.acquireSet(plan, base + "_one");
  acq.acquireSet(plan, base + "_s1", nullptr, {1, 2});  // lines 1 and 3
  acq.acquireSet(plan, base + "_s2", nullptr, {2, 2});  // line 2
  EXPECT_EQ(examples::loadExampleSet(base + "_s1").examples.size(), 2u);
  const std::string merge = std::string(DE_TOOL_DIR) + "/de_merge_examples --output " + base + "_merged " + base + "_s2 " +
                            base + "_s1 2>/dev/null";
  ASSERT_EQ(std::system(merge.c_str()), 0);
  const auto bytes = [](const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  EXPECT_EQ(bytes(base + "_merged/stamps.bin"), bytes(base + "_one/stamps.bin"));
  EXPECT_EQ(bytes(base + "_merged/manifest.json"), bytes(base + "_one/manifest.json"));
  // A shard of another scene, or the same shard twice, is refused and nothing is written.
  scene_file::SceneDescription other = de_test::tinySlab();
  other.stamp.resolution = 8;
  acquisition::SceneAcquisition(other).acquireSet({plan[1]}, base + "_other");
  for (const std::string& second : {base + "_other", base + "_s1"}) {
    std::filesystem::remove_all(base + "_merged");
    const std::string refused = std::string(DE_TOOL_DIR) + "/de_merge_examples --output " + base + "_merged " + base + "_s1 " +
                                second + " 2>/dev/null";
    EXPECT_NE(std::system(refused.c_str()), 0) << second;
    EXPECT_FALSE(std::filesystem::exists(base + "_merged"));
  }
  for (const char* d : {"_one", "_s1", "_s2", "_merged", "_other"}) std::filesystem::remove_all(base + d);
}

TEST(SceneAcquisition, ExamplesAreMadeOnARepairedSelfIntersectingSurface) {
  // test/data/dirty_surface: two overlapping lobes in one OBJ; tetgen alone refuses it.
  scene_file::SceneDescription d = scene_file::readSceneFile(std::string(DE_SOURCE_DIR) + "/test/data/dirty_surface/two_lobes.yaml");
  d.solve.indentSteps = 1;
  d.solve.dragSteps = 1;
  acquisition::SceneAcquisition acq(d);
  EXPECT_NE(acq.models().report.find("repaired: "), std::string::npos) << acq.models().report;
  const std::vector<acquisition::PlanEntry> plan = acquisition::autoPlan(acq, 2);
  const std::string dir = "/tmp/de_acq_" + std::to_string(::getpid()) + "_lobes";
  std::filesystem::remove_all(dir);
  const examples::ExampleSet set = acq.acquireSet(plan, dir);
  ASSERT_EQ(set.examples.size(), 2u);
  for (const examples::Example& e : set.examples) {
    EXPECT_TRUE(cv::checkRange(e.stamp));
    EXPECT_GT(cv::norm(e.stamp, cv::NORM_INF), 1e-6);  // the fine model adds detail the coarse one lacks
  }
  std::filesystem::remove_all(dir);
}

TEST(FineConvergence, TheTruthIsComparedAcrossFineModelsAtTheSameDisplayVertices) {
  const scene_file::SceneDescription d = de_test::tinySlab();
  const acquisition::FineConvergence c = acquisition::fineConvergence(d, {1.0, 2.0}, 1, 11);
  ASSERT_EQ(c.levels.size(), 2u);
  EXPECT_GT(c.levels[1].fineTets, c.levels[0].fineTets);
  ASSERT_EQ(c.contacts.size(), 1u);
  ASSERT_EQ(c.contacts[0].changeRms.size(), 1u);
  EXPECT_GT(c.contacts[0].vertices, 10);
  EXPECT_GT(c.contacts[0].coarseRms, 0.0);
  // A finer fine model moves the truth, by less than the coarse model is off.
  EXPECT_GT(c.contacts[0].changeRms[0], 0.0);
  EXPECT_LT(c.contacts[0].changeRms[0], c.contacts[0].coarseRms);
  EXPECT_DOUBLE_EQ(c.meanRelativeChange(0), c.contacts[0].changeRms[0] / c.contacts[0].coarseRms);
  EXPECT_DOUBLE_EQ(c.worstRelativeChange(0), c.meanRelativeChange(0));
  for (const std::vector<double>& bad : {std::vector<double>{2.0, 4.0}, {1.0, 1.0}, {}})
    EXPECT_THROW(acquisition::fineConvergence(d, bad, 1, 11), InvalidInputError);
  EXPECT_THROW(acquisition::fineConvergence(d, {1.0}, 0, 11), InvalidInputError);
}

TEST(FineConvergence, FinerModelsScaleCellsOrTheLargestTet) {
  const scene_file::SceneDescription slab = de_test::tinySlab();
  const scene_file::SceneDescription finer = acquisition::withFinerFineModel(slab, 8.0, {}, {});
  EXPECT_EQ(finer.procedural->fineCells, Eigen::Vector3i(24, 24, 4));
  EXPECT_EQ(finer.procedural->fineSkinLayers, 2);
  EXPECT_EQ(finer.procedural->coarseCells, slab.procedural->coarseCells);
  scene_file::SceneDescription file;
  file.surface = "organ.obj";
  file.fineMaxVolume = 1e-7;
  EXPECT_DOUBLE_EQ(acquisition::withFinerFineModel(file, 4.0, {}, {}).fineMaxVolume, 2.5e-8);
  EXPECT_THROW(acquisition::withFinerFineModel(file, 0.5, {}, {}), InvalidInputError);
}
