// The ROS-free EnrichmentSession (docs/design.md §6): the same result as the ContactEnricher it wraps, the
// unchanged-input memo, open surfaces in a volume, rest surfaces built off the frame thread, and bad input.
#include <gtest/gtest.h>

#include "../top_face.hpp"

#include "enricher_test_support.hpp"

#include <cmath>
#include <limits>
#include <mutex>
#include <optional>
#include <cstring>
#include <string>
#include <vector>

#include "deformation_enrichment/enrichment/contact_continuity.hpp"
#include "deformation_enrichment/enrichment/enrichment_session.hpp"
#include "deformation_enrichment/enrichment/example_set_options.hpp"
#include "deformation_enrichment/error.hpp"

using namespace deformation_enrichment;
using enrichment::EnrichmentSession;
using enrichment::FrameResult;

namespace {

const Eigen::Vector3d kContact(0.001, -0.002, 0.02);

// One example described at kContact on the test slab, with the descriptor options a set records.
examples::ExampleSet sessionSet() {
  enrichment::ContactEnricher enricher(de_test::slabSurface(), de_test::enricherOptions());
  enrichment::Contact contact;
  contact.point = kContact;
  const enrichment::ContactDescription d =
      enricher.describe(de_test::dented(enricher.restSurface().vertices, kContact, 1.0), contact);
  examples::ExampleSet set = de_test::oneExampleSet(d, de_test::syntheticStamp(32, 0.02), 0.02);
  set.metadata.material["window_scale_m"] = de_test::enricherOptions().descriptors.window.scale;
  set.metadata.material["site_sample_spacing_m"] = de_test::enricherOptions().sampleSpacing;
  return set;
}

struct LogCapture {
  std::mutex mutex;
  std::vector<std::string> lines;
  bool contains(const std::string& fragment) {
    std::lock_guard<std::mutex> lock(mutex);
    for (const auto& line : lines)
      if (line.find(fragment) != std::string::npos) return true;
    return false;
  }
};

enrichment::SessionOptions sessionOptions(LogCapture* log = nullptr) {
  enrichment::SessionOptions o;
  o.defaults = de_test::enricherOptions();
  if (log)
    o.log = [log](enrichment::SessionLogLevel, const std::string& text) {
      std::lock_guard<std::mutex> lock(log->mutex);
      log->lines.push_back(text);
    };
  return o;
}

// A session on `rest` with the test set, its enricher built.
std::unique_ptr<EnrichmentSession> readySession(const mesh::TriangleMesh& rest, std::optional<mesh::TetMesh> volume = {},
                                                LogCapture* log = nullptr) {
  auto session = std::make_unique<EnrichmentSession>(sessionOptions(log));
  session->setExampleSet(sessionSet());
  session->setRestGeometry({rest, std::move(volume), "test"});
  session->waitForRebuild();
  return session;
}

// The tool at the current position of the surface point under kContact.
std::vector<enrichment::ToolContact> toolAt(const Eigen::Matrix3Xf& current, const mesh::TriangleMesh& rest) {
  Eigen::Index nearest = 0;
  (rest.vertices.colwise() - kContact).colwise().squaredNorm().minCoeff(&nearest);
  return {{"tool", current.col(nearest).cast<double>()}};
}

Eigen::Matrix3Xf dentedState(const mesh::TriangleMesh& rest) {
  return de_test::dented(rest.vertices, kContact, 1.0).cast<float>();
}


mesh::TetMesh slabVolume() {
  return mesh::gridTetMesh(Eigen::Vector3d(-0.05, -0.05, 0.0), Eigen::Vector3d(0.05, 0.05, 0.02), Eigen::Vector3i(16, 16, 3));
}

}  // namespace

TEST(EnrichmentSession, EnrichesExactlyAsTheContactEnricherItWraps) {
  const mesh::TriangleMesh rest = de_test::slabSurface();
  auto session = readySession(rest);
  const Eigen::Matrix3Xf state = dentedState(rest);
  const auto tools = toolAt(state, rest);
  const FrameResult& result = session->enrich(state, tools, 1.0);
  ASSERT_EQ(result.kind, FrameResult::Kind::Enriched) << result.error;
  ASSERT_TRUE(result.changed);
  EXPECT_GT(result.confidence, 0.0f);

  const examples::ExampleSet set = sessionSet();
  enrichment::ContactEnricher reference(rest, enrichment::optionsFor(set, de_test::enricherOptions()));
  reference.setExamples(set);
  enrichment::ContactContinuity continuity;
  enrichment::Contact contact;
  contact.point = tools[0].point;
  contact.restState = false;
  enrichment::EnrichmentResult expected;
  reference.enrich(Eigen::Matrix3Xd(state.cast<double>()), continuity.contactsFor({contact}), expected);
  Eigen::Matrix3Xf enriched = state;
  for (std::size_t k = 0; k < expected.enrichment.vertices.size(); ++k)
    enriched.col(expected.enrichment.vertices[k]) += expected.enrichment.displacements.col(static_cast<Eigen::Index>(k)).cast<float>();
  EXPECT_EQ(result.verticesTouched, expected.enrichment.vertices.size());
  EXPECT_TRUE(session->enrichedPositions() == enriched) << "bit for bit";
}

TEST(EnrichmentSession, ReusesAnUnchangedInputAndPassesStatesWithoutContactsThrough) {
  const mesh::TriangleMesh rest = de_test::slabSurface();
  auto session = readySession(rest);
  const Eigen::Matrix3Xf state = dentedState(rest);
  const auto tools = toolAt(state, rest);
  ASSERT_EQ(session->enrich(state, tools, 1.0).kind, FrameResult::Kind::Enriched);
  // The second state differs in what continuity adds (the first state's frame axis); from then on the
  // inputs are identical.
  ASSERT_EQ(session->enrich(state, tools, 1.05).kind, FrameResult::Kind::Enriched);
  const Eigen::Matrix3Xf first = session->enrichedPositions();
  const FrameResult& again = session->enrich(state, tools, 1.1);
  EXPECT_EQ(again.kind, FrameResult::Kind::Reused);
  EXPECT_TRUE(again.changed);
  EXPECT_TRUE(session->enrichedPositions() == first);
  EXPECT_EQ(session->diagnostics().statesReused, 1u);
  Eigen::Matrix3Xf moved = state;
  moved(2, 0) += 1e-6f;  // far from the contact, but a different input
  EXPECT_EQ(session->enrich(moved, tools, 1.2).kind, FrameResult::Kind::Enriched);
  // The released site keeps enriching while the tissue is dented; at rest it goes and nothing is done.
  EXPECT_EQ(session->enrich(moved, {}, 1.3).kind, FrameResult::Kind::Enriched) << "the released site";
  const Eigen::Matrix3Xf flat = rest.vertices.cast<float>();
  session->enrich(flat, {}, 1.4);  // the released site sees the tissue at rest and goes
  const FrameResult& none = session->enrich(flat, {}, 1.5);
  EXPECT_EQ(none.kind, FrameResult::Kind::PassedThrough);
  EXPECT_FALSE(none.changed);
}

TEST(EnrichmentSession, AnOpenSurfaceInAVolumeIsEnrichedLikeTheClosedOne) {
  // A block 6 cm deep, deeper than the window's cut-off (4 h = 3.2 cm): the deformation descriptor's surface
  // samples are the top's in both. (On a thinner object the closed surface's far side enters mu's MLS fit,
  // which an open surface lacks: docs/accuracy.md, Open surfaces.)
  const mesh::TetMesh block = mesh::gridTetMesh(Eigen::Vector3d(-0.05, -0.05, -0.04), Eigen::Vector3d(0.05, 0.05, 0.02),
                                                Eigen::Vector3i(16, 16, 6));
  const mesh::TriangleMesh closed = mesh::extractSurface(block).surface;
  const mesh::TriangleMesh open = de_test::topFace(closed, 0.02);
  auto closedSession = readySession(closed);
  auto openSession = readySession(open, block);
  EXPECT_NE(openSession->diagnostics().siteDensity.find("volume"), std::string::npos) << openSession->diagnostics().siteDensity;
  const Eigen::Matrix3Xf state = dentedState(closed);
  ASSERT_EQ(closedSession->enrich(state, toolAt(state, closed), 1.0).kind, FrameResult::Kind::Enriched);
  const FrameResult& result = openSession->enrich(state, toolAt(state, open), 1.0);
  ASSERT_EQ(result.kind, FrameResult::Kind::Enriched) << result.error;
  const Eigen::Matrix3Xf closedAdded = closedSession->enrichedPositions() - state;
  const Eigen::Matrix3Xf openAdded = openSession->enrichedPositions() - state;
  // The same site density samples and the same surface samples: the same detail up to round-off.
  ASSERT_GT(closedAdded.norm(), 0.0f);
  EXPECT_LT((openAdded - closedAdded).norm(), 1e-3 * closedAdded.norm());
  // Without the volume, a shell under the open surface stands in for it.
  auto shellSession = readySession(open);
  EXPECT_NE(shellSession->diagnostics().siteDensity.find("shell"), std::string::npos);
  EXPECT_EQ(shellSession->enrich(state, toolAt(state, open), 1.0).kind, FrameResult::Kind::Enriched);
  EXPECT_TRUE(shellSession->enrichedPositions().allFinite());
}

TEST(EnrichmentSession, ANewRestSurfaceIsBuiltOffTheFrameThreadWhileStatesFlow) {
  const mesh::TriangleMesh small = de_test::slabSurface();
  auto session = readySession(small);
  // About 50k vertices: its build (site density, KD-trees) takes far longer than one state.
  const mesh::TriangleMesh large = mesh::extractSurface(mesh::gridTetMesh(
      Eigen::Vector3d(-0.05, -0.05, 0.0), Eigen::Vector3d(0.05, 0.05, 0.02), Eigen::Vector3i(150, 150, 2))).surface;
  session->setRestGeometry({large, std::nullopt, "large"});
  EXPECT_TRUE(session->diagnostics().rebuilding);
  const Eigen::Matrix3Xf oldState = dentedState(small);
  EXPECT_EQ(session->enrich(oldState, toolAt(oldState, small), 1.0).kind, FrameResult::Kind::Enriched)
      << "states of the old topology are enriched while the new one is built";
  const Eigen::Matrix3Xf newState = dentedState(large);
  // The build of 50k vertices takes a fifth of a second, a state microseconds: the new topology's first state
  // arrives while it runs and passes through unchanged, marked pending.
  const FrameResult& passed = session->enrich(newState, toolAt(newState, large), 1.1);
  EXPECT_EQ(passed.kind, FrameResult::Kind::PassedThrough) << "never enriched with the wrong enricher";
  EXPECT_TRUE(passed.restPending);
  session->waitForRebuild();
  EXPECT_EQ(session->diagnostics().restVertices, large.numVertices());
  EXPECT_THROW(session->enrich(oldState, {}, 1.2), InvalidInputError) << "the old topology is gone";
  const FrameResult& enriched = session->enrich(newState, toolAt(newState, large), 1.3);
  EXPECT_EQ(enriched.kind, FrameResult::Kind::Enriched) << enriched.error;
  EXPECT_FALSE(enriched.restPending);
}

TEST(EnrichmentSession, RestSurfacesArrivingFasterThanTheBuildEndWithTheNewest) {
  auto session = readySession(de_test::slabSurface());
  std::vector<mesh::TriangleMesh> cuts;
  for (int cells = 20; cells < 25; ++cells)
    cuts.push_back(mesh::extractSurface(mesh::gridTetMesh(Eigen::Vector3d(-0.05, -0.05, 0.0), Eigen::Vector3d(0.05, 0.05, 0.02),
                                                          Eigen::Vector3i(cells, cells, 2))).surface);
  for (const auto& cut : cuts) session->setRestGeometry({cut, std::nullopt, "cut"});
  session->setRestGeometry({cuts.back(), std::nullopt, "the same again"});  // ignored: nothing new
  session->waitForRebuild();
  const enrichment::SessionDiagnostics d = session->diagnostics();
  EXPECT_EQ(d.restVertices, cuts.back().numVertices());
  EXPECT_GE(d.rebuilds, 2u);
  EXPECT_LE(d.rebuilds, 1u + cuts.size()) << "superseded surfaces need not be built";
  const Eigen::Matrix3Xf state = dentedState(cuts.back());
  EXPECT_EQ(session->enrich(state, toolAt(state, cuts.back()), 1.0).kind, FrameResult::Kind::Enriched);
}

TEST(EnrichmentSession, BadRestSurfacesAreRefusedOrEnrichedWithTheirFlaws) {
  const mesh::TriangleMesh rest = de_test::slabSurface();
  LogCapture log;
  auto session = readySession(rest, std::nullopt, &log);
  mesh::TriangleMesh broken = rest;
  broken.triangles(0, 0) = static_cast<int>(rest.numVertices());
  EXPECT_THROW(session->setRestGeometry({broken, std::nullopt, "broken"}), InvalidInputError);
  EXPECT_EQ(session->diagnostics().restVertices, rest.numVertices()) << "the previous rest surface stays";

  // Flaws real display surfaces have: a duplicate vertex (a seam, kept apart like a cut), a zero-area
  // triangle and a non-manifold fin, all on the touched top.
  mesh::TriangleMesh flawed = rest;
  Eigen::Index top = 0;
  (rest.vertices.colwise() - kContact).colwise().squaredNorm().minCoeff(&top);
  flawed.vertices.conservativeResize(3, rest.numVertices() + 2);
  flawed.vertices.col(rest.numVertices()) = rest.vertices.col(top);                                // duplicate
  flawed.vertices.col(rest.numVertices() + 1) = rest.vertices.col(top) + Eigen::Vector3d(0, 0, 0.004);  // fin tip
  flawed.triangles.conservativeResize(3, rest.numTriangles() + 2);
  int neighbour = -1;
  for (Eigen::Index t = 0; t < rest.numTriangles() && neighbour < 0; ++t)
    for (int k = 0; k < 3; ++k)
      if (rest.triangles(k, t) == top) neighbour = rest.triangles((k + 1) % 3, t);
  flawed.triangles.col(rest.numTriangles()) = Eigen::Vector3i(top, neighbour, static_cast<int>(rest.numVertices()));  // zero area
  flawed.triangles.col(rest.numTriangles() + 1) = Eigen::Vector3i(top, neighbour, static_cast<int>(rest.numVertices() + 1));  // fin
  session->setRestGeometry({flawed, std::nullopt, "flawed"});
  session->waitForRebuild();
  ASSERT_EQ(session->diagnostics().restVertices, flawed.numVertices()) << session->diagnostics().lastRestError;
  EXPECT_TRUE(log.contains("1 non-manifold edges")) << "the log says what the surface has";
  EXPECT_TRUE(log.contains("1 duplicate vertices, 1 zero-area triangles; duplicate vertices are kept apart"));
  const Eigen::Matrix3Xf state = de_test::dented(flawed.vertices, kContact, 1.0).cast<float>();
  const FrameResult& result = session->enrich(state, toolAt(state, flawed), 1.0);
  EXPECT_EQ(result.kind, FrameResult::Kind::Enriched) << result.error;
  EXPECT_TRUE(session->enrichedPositions().allFinite());

  // A volume 5 cm aside, asked for explicitly: refused with the reason, the previous rest stays.
  enrichment::SessionOptions strict = sessionOptions(&log);
  strict.density.source = descriptors::SiteDensitySource::Volume;
  EnrichmentSession volumeOnly(strict);
  volumeOnly.setExampleSet(sessionSet());
  volumeOnly.setRestGeometry({rest, slabVolume(), "good volume"});
  volumeOnly.waitForRebuild();
  mesh::TetMesh aside = slabVolume();
  aside.vertices.row(0).array() += 0.05;
  volumeOnly.setRestGeometry({de_test::topFace(rest, 0.02), aside, "volume aside"});
  volumeOnly.waitForRebuild();
  EXPECT_TRUE(log.contains("rest surface from volume aside refused")) << "logged";
  EXPECT_NE(volumeOnly.diagnostics().lastRestError.find("farther than"), std::string::npos) << volumeOnly.diagnostics().lastRestError;
  EXPECT_EQ(volumeOnly.diagnostics().restVertices, rest.numVertices());
  EXPECT_NE(volumeOnly.diagnostics().siteDensity.find("volume"), std::string::npos);
}

TEST(EnrichmentSession, NonFiniteOrMisfittingStatesAreRefusedAndTheStreamGoesOn) {
  const mesh::TriangleMesh rest = de_test::slabSurface();
  auto session = readySession(rest);
  const Eigen::Matrix3Xf state = dentedState(rest);
  const auto tools = toolAt(state, rest);
  ASSERT_EQ(session->enrich(state, tools, 1.0).kind, FrameResult::Kind::Enriched);
  ASSERT_EQ(session->enrich(state, tools, 1.05).kind, FrameResult::Kind::Enriched);
  const Eigen::Matrix3Xf good = session->enrichedPositions();
  Eigen::Matrix3Xf bad = state;
  bad(1, 7) = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(session->enrich(bad, tools, 1.1), InvalidInputError);
  EXPECT_THROW(session->enrich(state.leftCols(10), tools, 1.1), InvalidInputError);
  const FrameResult& again = session->enrich(state, tools, 1.2);
  EXPECT_EQ(again.kind, FrameResult::Kind::Reused) << "the memo of the last good state survives";
  EXPECT_TRUE(session->enrichedPositions() == good);
  EnrichmentSession empty(sessionOptions());
  EXPECT_THROW(empty.enrich(state, tools, 1.0), InvalidInputError) << "no rest surface yet";
}

TEST(EnrichmentSession, KnobsApplyFromTheNextStateAndBadOnesChangeNothing) {
  const mesh::TriangleMesh rest = de_test::slabSurface();
  auto session = readySession(rest);
  const Eigen::Matrix3Xf state = dentedState(rest);
  const auto tools = toolAt(state, rest);
  session->enrich(state, tools, 1.0);
  const Eigen::Matrix3Xf full = session->enrichedPositions() - state;
  enrichment::KnobOptions half;
  half.gain.stampGain = 0.5;
  session->setKnobs(half);
  ASSERT_EQ(session->enrich(state, tools, 1.1).kind, FrameResult::Kind::Enriched) << "a knob invalidates the memo";
  const Eigen::Matrix3Xf halved = session->enrichedPositions() - state;
  EXPECT_NEAR(halved.norm(), 0.5 * full.norm(), 1e-3 * full.norm());
  enrichment::KnobOptions bad = half;
  bad.hermiteOrder = 5;  // the set stores mu up to order 2
  EXPECT_THROW(session->setKnobs(bad), InvalidInputError);
  bad = half;
  bad.sigmaRho = std::numeric_limits<double>::infinity();
  EXPECT_THROW(session->setKnobs(bad), InvalidInputError);
  bad = half;
  bad.gain.minConfidence = 1.5;
  EXPECT_THROW(session->setKnobs(bad), InvalidInputError);
  EXPECT_EQ(session->knobs().gain.stampGain, 0.5);
  EXPECT_EQ(session->knobs().hermiteOrder, 0);
  enrichment::KnobOptions lower = half;
  lower.hermiteOrder = 1;
  session->setKnobs(lower);
  EXPECT_EQ(session->diagnostics().hermiteOrder, 1);
  EXPECT_EQ(session->enrich(state, tools, 1.2).kind, FrameResult::Kind::Enriched);
}

TEST(EnrichmentSession, ASetOfAnotherMaterialIsScaledByTheMaterialSimilarity) {
  const mesh::TriangleMesh rest = de_test::slabSurface();
  examples::ExampleSet set = sessionSet();
  set.metadata.provenance = examples::Provenance{};
  set.metadata.provenance->scene.material = {1e4, 0.45};
  set.metadata.provenance->scene.name = "slab";
  const auto addedFor = [&](std::optional<scene_file::SceneDescription> scene, double& similarity, double transferGain = 0.0) {
    enrichment::SessionOptions options = sessionOptions();
    options.scene = std::move(scene);
    options.transferGain = transferGain;
    EnrichmentSession session(options);
    session.setExampleSet(set);
    session.setRestGeometry({rest, std::nullopt, "test"});
    session.waitForRebuild();
    similarity = session.diagnostics().materialSimilarity;
    const bool transfer = options.scene && options.scene->name != "slab";
    EXPECT_EQ(session.diagnostics().stampScale, transfer && transferGain > 0.0 ? transferGain : similarity);
    const Eigen::Matrix3Xf state = dentedState(rest);
    EXPECT_EQ(session.enrich(state, toolAt(state, rest), 1.0).kind, FrameResult::Kind::Enriched);
    const Eigen::Matrix3Xf added = session.enrichedPositions() - state;
    // A knob change keeps the enricher and the similarity: half the gain, half the detail.
    enrichment::KnobOptions half;
    half.gain.stampGain = 0.5;
    session.setKnobs(half);
    EXPECT_EQ(session.enrich(state, toolAt(state, rest), 1.1).kind, FrameResult::Kind::Enriched);
    const Eigen::Matrix3Xf halved = session.enrichedPositions() - state;
    EXPECT_NEAR(halved.norm(), 0.5 * added.norm(), 1e-3 * added.norm()) << "similarity " << similarity;
    return added;
  };
  double same = 0.0, softer = 0.0, unknown = 0.0;
  scene_file::SceneDescription tissue = set.metadata.provenance->scene;
  const Eigen::Matrix3Xf full = addedFor(tissue, same);
  tissue.material.young = 1.5e4;  // bulk and (no skin) skin 1.5 times stiffer: exp(-1/2)
  const Eigen::Matrix3Xf scaled = addedFor(tissue, softer);
  const Eigen::Matrix3Xf withoutScene = addedFor(std::nullopt, unknown);
  EXPECT_DOUBLE_EQ(same, 1.0);
  EXPECT_DOUBLE_EQ(unknown, 1.0);
  EXPECT_NEAR(softer, std::exp(-0.5), 1e-12);
  ASSERT_GT(full.norm(), 0.0f);
  EXPECT_NEAR(scaled.norm(), std::exp(-0.5) * full.norm(), 1e-3 * full.norm());
  EXPECT_TRUE(withoutScene == full) << "no scene: the stamps as acquired";
  // A calibrated transfer gain replaces the similarity for a set of another scene, not for the set's own.
  double transferred = 0.0, own = 0.0;
  scene_file::SceneDescription other = tissue;
  other.name = "liver";
  const Eigen::Matrix3Xf calibrated = addedFor(other, transferred, 3.0);
  EXPECT_NEAR(transferred, std::exp(-0.5), 1e-12);
  EXPECT_NEAR(calibrated.norm(), 3.0 * full.norm(), 3e-3 * full.norm());
  const Eigen::Matrix3Xf ownScene = addedFor(tissue, own, 3.0);
  EXPECT_NEAR(ownScene.norm(), std::exp(-0.5) * full.norm(), 1e-3 * full.norm());
  enrichment::SessionOptions negative = sessionOptions();
  negative.transferGain = -1.0;
  EXPECT_THROW(EnrichmentSession{negative}, InvalidInputError);
}
