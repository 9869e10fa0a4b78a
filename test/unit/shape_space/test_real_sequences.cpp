// The smoothing flow on real, noisy data, run as de_smooth runs it by default (captureSmoothing: reduced,
// tau 0.5, restoring force 0.05, GOAST's energy with the bending weight for the mesh size):
//  - every animation clip of both MD2 models of [assimp-testmodels] with Gaussian noise of 0.1-0.5 % of
//    the bounding-box diagonal, and a closed mesh of [CGAL-data] bent by a known smooth field with 0.2 %
//    noise, each must finish (after 3 steps every step accepted), lower eq. 4 at every step and make the
//    shapes' motion smoother (intrinsic temporal roughness, rigid-invariant like the energy);
//  - [Brandt16 Fig. 8]: over all clips the per-vertex Gaussian trajectory filter at the same smoothness
//    (compareWithFilter) changes edge lengths and volume more than the flow; after 3 steps it changes the
//    volume more on every clip where it needs "a lot of filtering" (a kernel of at least 1.5 frames);
//  - the near-static clips ("stand", "crstnd": 19 and 40 frames) smooth to a tenth of their roughness. With
//    16 subspace directions they kept x0.16-0.78 of it and
//    distorted more than the filter; with 64 the subspace holds every frame's own noise.
// The short run (CI) takes 3 steps per clip at one noise level each (0.1 .. 0.5 % in turn); DE_LONG_TESTS=1
// runs 10 steps per clip at every level, where the per-clip claims are not asserted: the flow changes the
// volume more on 4 of the 160 runs (faerie attack at 0.1-0.3 %, up to 21 % more; faerie crattak at 0.3 %,
// 1 % more) and the edge lengths on 11 (all five levels of faerie attack, up to 28 % more).
// A step may stall (no tau lowers eq. 4: smoothing and restoring force balance); the run then ends there.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "../missing_input.hpp"
#include "deformation_enrichment/error.hpp"
#include "real_sequences.hpp"

namespace ss = deformation_enrichment::shape_space;
namespace de = deformation_enrichment;
using namespace ss::test;

namespace {

constexpr double kLotOfFiltering = 1.5;  // frames

bool longRun() { return std::getenv("DE_LONG_TESTS") != nullptr; }

// The per-clip invariants; returns the comparison for the aggregate checks.
FilterComparison checkRun(const ss::ShapeSequence& input, int steps, const std::string& name) {
  const FilterComparison c = compareWithFilter(input, captureSmoothing(), steps);
  std::printf("%-22s %2zu fr %5ld v | eq.4 %.4g -> %.4g | roughness x%.3f (trajectories x%.3f) | filter sigma %5.2f%s "
              "vs step %2d (x%.3f vs x%.3f) | edge %.4f vs %.4f, volume %.4f vs %.4f | %.2f s vs %.4f s\n",
              name.c_str(), input.shapes.size(), long(input.numVertices()), c.pathEnergy.front(), c.pathEnergy.back(),
              c.roughnessAfter / c.roughnessBefore, c.trajectoryAfter / c.trajectoryBefore, c.filterTuning.sigma,
              c.filterTuning.reached ? "" : " (smoothest)", c.comparedStep, c.comparedRoughness / c.roughnessBefore,
              c.filterTuning.roughness / c.roughnessBefore, c.flow.edge, c.filter.edge, c.flow.volume, c.filter.volume,
              c.flowSeconds, c.filterSeconds);
  EXPECT_GE(c.accepted, longRun() ? 1 : steps) << name << ": a step stalled";
  EXPECT_EQ(c.unconverged, 0) << name;
  EXPECT_TRUE(c.monotone) << name << ": eq. 4 did not fall at every step";
  EXPECT_LT(c.roughnessAfter, c.roughnessBefore) << name;
  if (!longRun() && c.filterTuning.sigma >= kLotOfFiltering) {
    EXPECT_LT(c.flow.volume, c.filter.volume) << name << " (sigma " << c.filterTuning.sigma << ")";
  }
  return c;
}

}  // namespace

TEST(RealSequences, EveryMd2ClipSmoothsWithFallingPathEnergyAndLessDistortionThanTheFilter) {
  const int steps = longRun() ? 10 : 3;
  Distortion flowSum, filterSum;
  int runs = 0, clipIndex = 0;
  for (const char* model : {"faerie", "sydney"}) {
    const de::mesh::Md2Animation animation = de::mesh::readMd2(std::string(kMd2Directory) + model + ".md2");
    const std::vector<Clip> clips = md2Clips(animation);
    ASSERT_EQ(clips.size(), 16u) << model;
    for (const Clip& clip : clips) {
      const int firstLevel = longRun() ? 1 : 1 + clipIndex % 5, lastLevel = longRun() ? 5 : firstLevel;
      for (int level = firstLevel; level <= lastLevel; ++level) {  // noise 0.1 .. 0.5 % of the diagonal
        const std::string name = std::string(model) + " " + clip.name + " " + std::to_string(level) + "e-3";
        const ss::ShapeSequence input = noisyClip(animation, clip, 0.001 * level, unsigned(100 + 5 * clipIndex + level));
        const FilterComparison c = checkRun(input, steps, name);
        if (clip.name == "stand" || clip.name == "crstnd") {
          EXPECT_LT(c.roughnessAfter, 0.1 * c.roughnessBefore) << name << ": a near-static clip barely smoothed";
        }
        flowSum.edge += c.flow.edge;
        flowSum.volume += c.flow.volume;
        filterSum.edge += c.filter.edge;
        filterSum.volume += c.filter.volume;
        ++runs;
      }
      ++clipIndex;
    }
  }
  EXPECT_EQ(runs, longRun() ? 160 : 32);
  EXPECT_LT(flowSum.edge, filterSum.edge);
  EXPECT_LT(flowSum.volume, filterSum.volume);
}

// The elephant of [CGAL-data] bent by a known smooth field, with 0.2 % noise.
class BentCgalMesh : public ::testing::Test {
protected:
  void SetUp() override {
    try {
      rest_ = cgalMesh("elephant");
    } catch (const de::IoError& e) {
      DE_MISSING_INPUT(e.what() << " (Debian libcgal-demo)");
    }
  }
  ss::ShapeSequence bent(int frames) const { return {rest_.triangles, withNoise(bentSequence(rest_, frames, 1.5), 0.002, 5)}; }
  de::mesh::TriangleMesh rest_;
};

TEST_F(BentCgalMesh, SmoothsLikeTheClips) {
  const ss::ShapeSequence input = bent(12);
  ss::validateSequence(input, 3);
  const FilterComparison c = checkRun(input, longRun() ? 10 : 3, "elephant bent 2e-3");
  EXPECT_GT(c.filterTuning.sigma, kLotOfFiltering);  // a smooth bend with noise: the filter needs a wide kernel
}

// A longer moving sequence (40 frames, more directions than a 16-direction subspace holds): with 16
// directions it kept x0.58 of its roughness after 10 steps; with every direction it reaches a tenth in 3.
TEST_F(BentCgalMesh, LongSequenceSmoothsInEveryDirection) {
  const FilterComparison c = checkRun(bent(40), 3, "elephant bent 40 frames 2e-3");
  EXPECT_LT(c.roughnessAfter, 0.1 * c.roughnessBefore);
  EXPECT_LT(c.trajectoryAfter, 0.1 * c.trajectoryBefore);
}

// Each shape's next average starts from the quasi-Newton model its last one ended with (SmoothingFlow::accept):
// the steps after the first need fewer solver iterations (measured on a 24-frame bent elephant: 70-119 per
// step instead of 148-166; with the rest Hessians every step took about as many as the first).
TEST_F(BentCgalMesh, LaterStepsStartFromThePreviousModels) {
  const ss::ShapeSequence input = bent(24);
  const ss::DiscreteShells energy(input.triangles, input.numVertices(), ss::DiscreteShellsOptions::hyperelasticFor(input.shapes.front()));
  ss::SmoothingFlow flow(energy, input, captureSmoothing());
  std::vector<int> iterations;
  for (int k = 0; k < 4; ++k) {
    const ss::FlowStep step = flow.step();
    ASSERT_TRUE(step.converged()) << "step " << k;
    iterations.push_back(step.solverIterations);
  }
  std::printf("solver iterations per step: %d %d %d %d\n", iterations[0], iterations[1], iterations[2], iterations[3]);
  EXPECT_LT(iterations[3], 0.75 * iterations[0]);
}

// The filter the flow is held to: with the end shapes fixed, a short clip's filtered roughness falls and then
// rises with the width (the interior shapes approach their mean), so "the widest filter" is not the smoothest;
// the comparison must use the narrowest width as smooth as the target, else the smoothest one.
TEST(RealSequences, FilterTuningIsTheNarrowestWidthAsSmoothOrElseTheSmoothest) {
  const de::mesh::Md2Animation anim = de::mesh::readMd2(std::string(kMd2Directory) + "sydney.md2");
  const ss::ShapeSequence input = noisyClip(anim, Clip{"crwalk", 154, 159}, 0.003, 21);
  const auto roughness = [&](const Shapes& x) { return intrinsicRoughness(x, input.triangles); };
  const double widest = roughness(gaussianFilter(input.shapes, 20.0));
  const FilterTuning smoothest = tuneFilter(input.shapes, 0.0, roughness);
  EXPECT_FALSE(smoothest.reached);
  EXPECT_LT(smoothest.sigma, 5.0);
  EXPECT_LT(smoothest.roughness, 0.9 * widest);
  EXPECT_NEAR(smoothest.roughness, roughness(gaussianFilter(input.shapes, smoothest.sigma)), 1e-9 * smoothest.roughness);

  const double target = 2.0 * smoothest.roughness;  // reachable: the narrowest width with at most this roughness
  const FilterTuning narrowest = tuneFilter(input.shapes, target, roughness);
  EXPECT_TRUE(narrowest.reached);
  EXPECT_LE(narrowest.roughness, target);
  EXPECT_LT(narrowest.sigma, smoothest.sigma);
  EXPECT_GT(roughness(gaussianFilter(input.shapes, 0.99 * narrowest.sigma)), target);
}

TEST(RealSequences, DegenerateFramesOfRealDataAreRejected) {
  // sydney.md2's frame 28 has zero-area triangles after 8-bit quantisation.
  const de::mesh::Md2Animation anim = de::mesh::readMd2(std::string(kMd2Directory) + "sydney.md2");
  std::vector<de::mesh::TriangleMesh> frames(anim.frames.begin() + 26, anim.frames.begin() + 30);
  try {
    ss::makeSequence(frames);
    FAIL() << "degenerate frame accepted";
  } catch (const de::InvalidInputError& e) {
    EXPECT_NE(std::string(e.what()).find("shape 2"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("degenerate"), std::string::npos) << e.what();
  }
}
