#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <unistd.h>

#include "deformation_enrichment/acquisition/held_out_evaluation.hpp"
#include "deformation_enrichment/acquisition/scene_acquisition.hpp"
#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/examples/example_set_io.hpp"
#include "tiny_slab.hpp"

using namespace deformation_enrichment;

namespace {

acquisition::PlanEntry entry(double x, double y, double depth, double dx) {
  acquisition::PlanEntry e;
  e.point = Eigen::Vector3d(x, y, 0.02);
  e.depth = depth;
  e.drag = Eigen::Vector3d(dx, 0.0, 0.0);
  return e;
}

std::string temporary(const std::string& name) { return "/tmp/de_recorded_" + std::to_string(::getpid()) + "_" + name; }

void write(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

}  // namespace

TEST(RecordedCoarse, TheOwnCoarseStateGivenBackGivesTheOwnExample) {
  // A recording of the package's own coarse model: descriptors and the fine half are the same, and the
  // volume stamp, whose coarse half inside the volume is fitted to the surface, places nearly the same
  // detail on the display surface (where the run time looks it up).
  acquisition::SceneAcquisition acq(de_test::tinySlab());
  const acquisition::PlanEntry e = entry(0.004, -0.003, 0.003, 0.002);
  const acquisition::InteractionResult own = acq.simulate(e);
  const acquisition::InteractionResult recorded = acq.simulate(e, own.coarseOnFine);
  EXPECT_LT((recorded.fine - own.fine).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_EQ((recorded.coarseOnFine - own.coarseOnFine).cwiseAbs().maxCoeff(), 0.0);
  const examples::Example a = acq.makeExample(e, own), b = acq.makeExample(e, recorded);
  EXPECT_EQ((a.rho.values() - b.rho.values()).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ((a.mu.values() - b.mu.values()).cwiseAbs().maxCoeff(), 0.0);
  enrichment::Contact contact = acq.contactOf(e);
  const enrichment::ContactDescription d = acq.enricher().describe(own.coarseOnFine, contact);
  enrichment::SurfaceEnrichment placedOwn, placedRecorded;
  acq.enricher().placeStamp(d, a.stamp, a.stampRadius, a.stampLayers, placedOwn);
  acq.enricher().placeStamp(d, b.stamp, b.stampRadius, b.stampLayers, placedRecorded);
  ASSERT_EQ(placedOwn.vertices, placedRecorded.vertices);
  const double relative = (placedOwn.displacements - placedRecorded.displacements).norm() / placedOwn.displacements.norm();
  EXPECT_LT(relative, 0.01) << "the placed detail differs by " << relative;  // measured 7e-4
  EXPECT_GT(relative, 0.0);  // the fit is not the solve: the interior differs
}

TEST(RecordedCoarse, StatesOfTheWrongSizeOrNotFiniteAreRefused) {
  acquisition::SceneAcquisition acq(de_test::tinySlab());
  const acquisition::PlanEntry e = entry(0.0, 0.0, 0.002, 0.0);
  const Eigen::Index n = acq.fineSurface().numVertices();
  try {
    acq.simulate(e, Eigen::Matrix3Xd::Zero(3, n - 1));
    FAIL() << "no error";
  } catch (const InvalidInputError& error) {
    EXPECT_NE(std::string(error.what()).find(std::to_string(n - 1) + " points for a display surface of " + std::to_string(n)),
              std::string::npos)
        << error.what();
  }
  Eigen::Matrix3Xd state = acq.fineSurface().vertices;
  state(2, 5) = std::numeric_limits<double>::infinity();
  EXPECT_THROW(acq.simulate(e, state), InvalidInputError);
}

TEST(RecordedCoarse, ASetFromARecordingNamesItAndLeavesOutLinesWithoutAState) {
  acquisition::SceneAcquisition acq(de_test::tinySlab());
  acquisition::RecordedCoarse coarse;
  coarse.path = temporary("session.bag");
  write(coarse.path, "recording one");
  coarse.simulator = "/bullet_coarse_sim";
  coarse.plan = {entry(0.0, 0.0, 0.002, 0.0), entry(0.01, 0.005, 0.003, 0.002)};
  coarse.settled[1] = acq.simulate(coarse.plan[1]).coarseOnFine;
  const std::string dir = temporary("set");
  std::filesystem::remove_all(dir);
  std::ostringstream log;
  const examples::ExampleSet set = acq.acquireSet(coarse.plan, dir, &log, {}, &coarse);
  ASSERT_EQ(set.examples.size(), 1u);
  EXPECT_EQ(set.examples[0].planLine, 1);
  EXPECT_NE(log.str().find("plan line 1: no settled coarse state in " + coarse.path + ", left out"), std::string::npos) << log.str();
  const examples::ExampleSet loaded = examples::loadExampleSet(dir);
  ASSERT_TRUE(loaded.metadata.provenance);
  EXPECT_EQ(loaded.metadata.provenance->coarseSimulator, "/bullet_coarse_sim");
  EXPECT_EQ(loaded.metadata.provenance->fileHashes.count("de_recorded_" + std::to_string(::getpid()) + "_session.bag"), 1u);
  // The same recording resumes; another recording (other bytes) starts over.
  std::ostringstream again;
  acq.acquireSet(coarse.plan, dir, &again, {}, &coarse);
  EXPECT_NE(again.str().find("already acquired"), std::string::npos) << again.str();
  write(coarse.path, "recording two");
  std::ostringstream other;
  acq.acquireSet(coarse.plan, dir, &other, {}, &coarse);
  EXPECT_NE(other.str().find("starting over"), std::string::npos) << other.str();
  // The package's own coarse model is another source too.
  std::ostringstream own;
  acq.acquireSet(coarse.plan, dir, &own);
  EXPECT_NE(own.str().find("starting over"), std::string::npos) << own.str();
  std::filesystem::remove_all(dir);
  std::filesystem::remove(coarse.path);
}

TEST(RecordedCoarse, HeldOutInteractionsWithoutAStateAreRefusedBeforeAnySolve) {
  acquisition::SceneAcquisition acq(de_test::tinySlab());
  acquisition::RecordedCoarse coarse;
  coarse.path = "held_out.bag";
  coarse.plan = {entry(0.0, 0.0, 0.002, 0.0), entry(0.01, 0.005, 0.003, 0.0)};
  coarse.settled[0] = acq.fineSurface().vertices;
  int solved = 0;
  try {
    acquisition::simulateHeldOut(acq, coarse.plan, [&](std::size_t) { ++solved; }, &coarse);
    FAIL() << "no error";
  } catch (const InvalidInputError& error) {
    EXPECT_NE(std::string(error.what()).find("held-out interaction 2 has no settled coarse state in held_out.bag"), std::string::npos)
        << error.what();
  }
  EXPECT_EQ(solved, 0);
}
