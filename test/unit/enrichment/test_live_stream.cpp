// A live stream that holds still (docs/design.md §8): contacts where they are (no snapping to vertices), bounded
// blends, a smooth confidence gate, released sites after lift-off and the temporal filter.
#include <gtest/gtest.h>

#include "enricher_test_support.hpp"

#include <cmath>
#include <limits>

#include "deformation_enrichment/enrichment/contact_continuity.hpp"
#include "deformation_enrichment/enrichment/contact_enricher.hpp"
#include "deformation_enrichment/enrichment/temporal_filter.hpp"
#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/grid_tet_mesh.hpp"
#include "deformation_enrichment/mesh/tet_surface.hpp"
#include "deformation_enrichment/smooth_ramp.hpp"

using namespace deformation_enrichment;
using enrichment::Contact;
using enrichment::ContactEnricher;

namespace {

using de_test::slabSurface;
enrichment::ContactEnricherOptions options() { return de_test::enricherOptions(); }

// A press of `depth` under `centre`, fading into the slab.
Eigen::Matrix3Xd pressed(const Eigen::Matrix3Xd& rest, const Eigen::Vector3d& centre, double depth) {
  Eigen::Matrix3Xd current = rest;
  for (Eigen::Index v = 0; v < rest.cols(); ++v)
    current(2, v) -= depth * std::exp(-(rest.col(v) - centre).squaredNorm() / (2.0 * 0.008 * 0.008)) * rest(2, v) / 0.02;
  return current;
}

cv::Mat wavyStamp(int n, double radius) {
  cv::Mat stamp(n, n, CV_32FC3);
  for (int j = 0; j < n; ++j)
    for (int k = 0; k < n; ++k) {
      const double phi = -radius + 2.0 * radius * k / (n - 1), varphi = -radius + 2.0 * radius * j / (n - 1);
      stamp.at<cv::Vec3f>(j, k) = cv::Vec3f(0.0f, 0.0f, static_cast<float>(1e-3 * std::sin(200.0 * phi) * std::cos(100.0 * varphi)));
    }
  return stamp;
}

// One example: the press of 2 mm at `p`, with the wavy stamp.
examples::ExampleSet pressExample(const ContactEnricher& enricher, const Eigen::Vector3d& p) {
  Contact c;
  c.point = p;
  const auto d = enricher.describe(pressed(enricher.restSurface().vertices, p, 0.002), c);
  examples::Example e;
  e.contact = d.p;
  e.frame = d.B;
  e.rho = d.rho;
  e.mu = d.mu;
  e.stamp = wavyStamp(32, 0.02);
  e.stampRadius = 0.02;
  e.sceneId = "synthetic";
  examples::ExampleSet set;
  set.metadata.scene = "synthetic";
  set.examples.push_back(e);
  return set;
}

enrichment::ExampleBlenderOptions fixedWidths() {
  enrichment::ExampleBlenderOptions b;
  b.fitWidths = false;
  b.widths.sigmaRho = 0.05;
  b.widths.sigmaU = 0.3;
  return b;
}

Contact currentContact(const Eigen::Vector3d& p, int tool = 0) {
  Contact c;
  c.point = p;
  c.restState = false;
  c.toolId = tool;
  return c;
}

}  // namespace

TEST(LiveStream, CurrentContactLiesOnItsTriangleNotOnAVertex) {
  ContactEnricher enricher(slabSurface(), options());
  const mesh::TriangleMesh& rest = enricher.restSurface();
  // A point 0.5 mm above a top triangle's centroid, on the undeformed surface: its rest point is the
  // centroid itself, with barycentric coordinates 1/3.
  Eigen::Index top = 0;
  for (Eigen::Index f = 0; f < rest.triangles.cols(); ++f)
    if ((rest.vertices(Eigen::all, rest.triangles.col(f)).row(2).array() > 0.0199).all()) top = f;
  const Eigen::Vector3d centroid = rest.vertices(Eigen::all, rest.triangles.col(top)).rowwise().mean();
  const auto d = enricher.describe(rest.vertices, currentContact(centroid + Eigen::Vector3d(0, 0, 0.0005)));
  EXPECT_LT((d.p - centroid).norm(), 1e-12);
  EXPECT_LT((d.barycentric - Eigen::Vector3d::Constant(1.0 / 3.0)).norm(), 1e-9);
  // On a pressed surface the same barycentric point of the current triangle maps back to the rest centroid.
  const Eigen::Matrix3Xd current = pressed(rest.vertices, centroid, 0.002);
  const Eigen::Vector3d onCurrent = current(Eigen::all, rest.triangles.col(top)).rowwise().mean();
  EXPECT_LT((enricher.describe(current, currentContact(onCurrent)).p - centroid).norm(), 1e-9);
}

// Largest frame-to-frame change of rho (relative) and of B while a press slides 1 cm in steps of `step`;
// the rest point must follow the tool exactly (no snap to a vertex).
std::pair<double, double> slide(const ContactEnricher& enricher, double step) {
  const Eigen::Matrix3Xd& rest = enricher.restSurface().vertices;
  std::optional<enrichment::ContactDescription> previous;
  double rhoStep = 0.0, frameStep = 0.0;
  const int frames = static_cast<int>(std::lround(0.01 / step));
  for (int k = 0; k <= frames; ++k) {
    const Eigen::Vector3d centre(-0.005 + step * k, 0.001, 0.02);
    Contact c = currentContact(centre - Eigen::Vector3d(0, 0, 0.002));
    if (previous) c.previousFrameAxis = previous->B.col(0);
    const auto d = enricher.describe(pressed(rest, centre, 0.002), c);
    EXPECT_LT((d.p - centre).norm(), 2e-5) << "frame " << k << ": the rest point is where the tool is";
    if (previous) {
      rhoStep = std::max(rhoStep, (d.rho.values() - previous->rho.values()).norm() / d.rho.values().norm());
      frameStep = std::max(frameStep, (d.B - previous->B).norm());
    }
    previous = d;
  }
  return {rhoStep, frameStep};
}

TEST(LiveStream, SlidingContactMovesItsDescriptorsContinuously) {
  // Across 6.25 mm cells: the changes shrink with the step (continuity; a snap or a flip of b_x would
  // stay as large), and no step turns B by anything near a flip (|dB| = 2) or a quarter turn (1.41).
  ContactEnricher enricher(slabSurface(), options());
  const auto [rhoCoarse, frameCoarse] = slide(enricher, 1e-4);
  const auto [rhoFine, frameFine] = slide(enricher, 5e-5);
  EXPECT_LT(rhoCoarse, 1e-3);
  EXPECT_LT(rhoFine, 0.7 * rhoCoarse);
  EXPECT_LT(frameCoarse, 0.5);
  EXPECT_LT(frameFine, 0.7 * frameCoarse);
}

TEST(LiveStream, MagnitudeRatioAndWeightsAreBounded) {
  const Eigen::Vector3d p(0.0, 0.001, 0.02);
  auto unbounded = options();
  unbounded.maxMagnitudeRatio = std::numeric_limits<double>::infinity();
  auto bounded = options();
  bounded.maxMagnitudeRatio = 2.0;
  ContactEnricher free(slabSurface(), unbounded), clamped(slabSurface(), bounded);
  for (auto* e : {&free, &clamped}) e->setExamples(pressExample(*e, p), fixedWidths());
  const Eigen::Matrix3Xd deep = pressed(free.restSurface().vertices, p, 0.01);  // 5 times the example's press
  Contact c;
  c.point = p;
  enrichment::EnrichmentResult a, b;
  free.enrich(deep, {c}, a);
  clamped.enrich(deep, {c}, b);
  const double ratio = a.contacts[0].muNorm / free.describe(pressed(free.restSurface().vertices, p, 0.002), c).mu.values().norm();
  ASSERT_GT(ratio, 3.0);
  ASSERT_EQ(a.enrichment.vertices, b.enrichment.vertices);
  // Stamps are blended in single precision.
  EXPECT_LT((b.enrichment.displacements - a.enrichment.displacements * (2.0 / ratio)).norm(), 1e-6 * a.enrichment.displacements.norm());
  auto bad = options();
  bad.maxWeight = 0.0;
  EXPECT_THROW(ContactEnricher(slabSurface(), bad), InvalidInputError);
  bad = options();
  bad.gain.minConfidence = 1.5;
  EXPECT_THROW(ContactEnricher(slabSurface(), bad), InvalidInputError);
}

TEST(LiveStream, ConfidenceGateIsARamp) {
  const Eigen::Vector3d p(0.0, 0.001, 0.02);
  ContactEnricher enricher(slabSurface(), options());
  enricher.setExamples(pressExample(enricher, p), fixedWidths());
  Contact c;
  c.point = p + Eigen::Vector3d(0.002, 0, 0);
  const Eigen::Matrix3Xd state = pressed(enricher.restSurface().vertices, c.point, 0.0015);
  enrichment::EnrichmentResult full, gated;
  enricher.enrich(state, {c}, full);
  const double confidence = full.contacts[0].confidence;
  ASSERT_GT(confidence, 0.05);
  for (double floor : {0.4 * confidence, 0.6 * confidence, 0.9 * confidence}) {
    enricher.setDetailGain({1.0, floor});
    enricher.enrich(state, {c}, gated);
    const double expected = smoothRamp(confidence, floor);
    EXPECT_NEAR(gated.contacts[0].detailScale, expected, 1e-12);
    EXPECT_LT((gated.enrichment.displacements - expected * full.enrichment.displacements).norm(),
              1e-6 * full.enrichment.displacements.norm() + 1e-15);
  }
  EXPECT_THROW(enricher.setDetailGain({1.0, -0.1}), InvalidInputError);
}

TEST(LiveStream, WeightNormBoundScalesTheRegressionDetail) {
  // detail x min(1, bound / sum_i |w_i|) for blend regression; the paper's blend ignores the bound.
  const Eigen::Vector3d p(0.0, 0.001, 0.02), q(0.004, 0.001, 0.02);
  Contact c;
  c.point = p + Eigen::Vector3d(0.001, 0, 0);
  for (auto method : {enrichment::BlendMethod::Regression, enrichment::BlendMethod::Paper}) {
    ContactEnricher enricher(slabSurface(), options());
    auto set = pressExample(enricher, p);
    set.examples.push_back(pressExample(enricher, q).examples[0]);
    auto blending = fixedWidths();
    blending.method = method;
    enricher.setExamples(set, blending);
    const Eigen::Matrix3Xd state = pressed(enricher.restSurface().vertices, c.point, 0.003);
    enrichment::EnrichmentResult full, bounded;
    enricher.setDetailGain({1.0, 0.0, 0.0});
    enricher.enrich(state, {c}, full);
    const double norm = full.contacts[0].weights.lpNorm<1>();
    ASSERT_GT(norm, 0.1);
    ASSERT_GT(full.enrichment.displacements.norm(), 0.0);
    for (double bound : {0.5 * norm, 0.9 * norm, 2.0 * norm}) {
      enricher.setDetailGain({1.0, 0.0, bound});
      enricher.enrich(state, {c}, bounded);
      const double expected = method == enrichment::BlendMethod::Regression ? std::min(1.0, bound / norm) : 1.0;
      EXPECT_NEAR(bounded.contacts[0].detailScale, expected, 1e-12) << toString(method) << " bound " << bound;
      EXPECT_LT((bounded.enrichment.displacements - expected * full.enrichment.displacements).norm(),
                1e-6 * full.enrichment.displacements.norm());
    }
    EXPECT_THROW(enricher.setDetailGain({1.0, 0.0, -1.0}), InvalidInputError);
    EXPECT_THROW(enricher.setDetailGain({1.0, 0.0, std::numeric_limits<double>::quiet_NaN()}), InvalidInputError);
  }
}

TEST(LiveStream, SmoothRampIsContinuousFromZeroToOne) {
  EXPECT_EQ(smoothRamp(0.5, 1.0), 0.0);
  EXPECT_EQ(smoothRamp(1.0, 1.0), 0.0);
  EXPECT_DOUBLE_EQ(smoothRamp(1.5, 1.0), 0.5);
  EXPECT_EQ(smoothRamp(2.0, 1.0), 1.0);
  EXPECT_EQ(smoothRamp(7.0, 1.0), 1.0);
  EXPECT_EQ(smoothRamp(0.3, 0.0), 1.0);
  EXPECT_EQ(smoothRamp(0.0, 0.0), 0.0);
  double previous = 0.0;
  for (int k = 0; k <= 1000; ++k) {
    const double r = smoothRamp(0.8 + 1.4 * k / 1000.0, 1.0);
    EXPECT_GE(r, previous);
    EXPECT_LE(r - previous, 1.5 * 1.4 / 1000.0 + 1e-12);  // slope at most 1.5 / floor
    previous = r;
  }
}

TEST(LiveStream, ReleasedSiteKeepsItsDetailAndFadesWithTheTissue) {
  const Eigen::Vector3d p(0.0, 0.001, 0.02);
  ContactEnricher enricher(slabSurface(), options());
  enricher.setExamples(pressExample(enricher, p), fixedWidths());
  const Eigen::Matrix3Xd& rest = enricher.restSurface().vertices;
  enrichment::ContactContinuity continuity;
  enrichment::EnrichmentResult result;
  const auto frame = [&](double depth, bool touching) {
    std::vector<Contact> contacts;
    if (touching) contacts.push_back(currentContact(p - Eigen::Vector3d(0, 0, depth), 7));
    enricher.enrich(pressed(rest, p, depth), continuity.contactsFor(contacts), result);
    continuity.update(result);
    return result.enrichment.displacements.norm();
  };
  const double held = frame(0.002, true);
  ASSERT_GT(held, 0.0);
  EXPECT_NEAR(frame(0.002, false), held, 1e-9 * held) << "lift-off with the tissue still dented keeps the detail";
  ASSERT_EQ(result.contacts.size(), 1u);
  EXPECT_EQ(result.contacts[0].toolId, 7);
  EXPECT_EQ(continuity.releasedSites(), 1u);
  EXPECT_NEAR(frame(0.001, false), 0.5 * held, 0.05 * held) << "fades with the deformation";
  EXPECT_EQ(frame(0.0, false), 0.0) << "back at rest: no detail";
  EXPECT_EQ(continuity.releasedSites(), 0u) << "the relaxed site is dropped";
  EXPECT_TRUE(continuity.contactsFor({}).empty());
  // A tool that returns takes over its released site.
  frame(0.002, true);
  frame(0.002, false);
  EXPECT_NEAR(frame(0.002, true), held, 1e-9 * held);
  EXPECT_EQ(continuity.releasedSites(), 0u);
  EXPECT_EQ(result.contacts.size(), 1u);
  EXPECT_THROW(continuity.contactsFor({currentContact(p, 1), currentContact(p, 1)}), InvalidInputError);
  enrichment::ContactContinuityOptions off;
  off.followRelease = false;
  enrichment::ContactContinuity without(off);
  without.contactsFor({currentContact(p, 1)});
  without.update(result);
  EXPECT_TRUE(without.contactsFor({}).empty());
}

// What ContactEnricher::enrich would report for `contacts`: each contact's rest point is its point, its
// frame axis `axes[i]`, |mu| 1.
enrichment::EnrichmentResult outcomes(const std::vector<Contact>& contacts, const std::vector<Eigen::Vector3d>& axes) {
  enrichment::EnrichmentResult result;
  for (std::size_t i = 0; i < contacts.size(); ++i) {
    enrichment::ContactOutcome o;
    o.toolId = contacts[i].toolId;
    o.description.p = contacts[i].point;
    o.description.B.col(0) = axes[i];
    o.muNorm = 1.0;
    result.contacts.push_back(o);
  }
  return result;
}

TEST(LiveStream, SitesGoWithTheTouchedPlaceNotWithToolIds) {
  enrichment::ContactContinuity continuity;  // match radius 5 mm
  const Eigen::Vector3d p1(-0.01, 0, 0.02), p2(0.01, 0, 0.02), a1 = Eigen::Vector3d::UnitX(), a2 = -Eigen::Vector3d::UnitY();
  std::vector<Contact> now = continuity.contactsFor({currentContact(p1, 1), currentContact(p2, 2)});
  ASSERT_EQ(now.size(), 2u);
  EXPECT_FALSE(now[0].previousFrameAxis) << "new sites have no history";
  continuity.update(outcomes(now, {a1, a2}));
  // The two tools swap ids (and move 1 mm): each contact continues the site it touches.
  now = continuity.contactsFor({currentContact(p2 + Eigen::Vector3d(0.001, 0, 0), 1), currentContact(p1, 2)});
  ASSERT_EQ(now.size(), 2u) << "no site is released by a swap";
  ASSERT_TRUE(now[0].previousFrameAxis && now[1].previousFrameAxis);
  EXPECT_EQ(*now[0].previousFrameAxis, a2);
  EXPECT_EQ(*now[1].previousFrameAxis, a1);
  EXPECT_EQ(continuity.releasedSites(), 0u);
  continuity.update(outcomes(now, {a2, a1}));
  // Tool 1 jumps 2 cm away (farther than the match radius): it starts afresh and its old site is released;
  // tool 2 lifted off: its site is released too.
  now = continuity.contactsFor({currentContact(p2 + Eigen::Vector3d(0.02, 0, 0), 1)});
  ASSERT_EQ(now.size(), 3u);
  EXPECT_FALSE(now[0].previousFrameAxis);
  EXPECT_EQ(continuity.releasedSites(), 2u);
  for (std::size_t i = 1; i < 3; ++i) {
    EXPECT_TRUE(now[i].restState);
    EXPECT_NE(now[i].toolId, 1) << "a released site keeps an id no touching tool has";
  }
  EXPECT_THROW(enrichment::ContactContinuity({true, 0.02, 0.0}), InvalidInputError);
}

TEST(LiveStream, TemporalFilterIsTheExactFirstOrderLowPass) {
  enrichment::TemporalFilter filter(0.05);
  const double dt = 1.0 / 60.0, alpha = 1.0 - std::exp(-dt / 0.05);
  enrichment::SurfaceEnrichment field{{2, 5}, Eigen::Matrix3Xd::Constant(3, 2, 1e-3)};
  filter.filter(field, dt, 10);  // a first call passes unchanged
  EXPECT_EQ(field.vertices, (std::vector<int>{2, 5}));
  EXPECT_EQ(field.displacements, Eigen::Matrix3Xd::Constant(3, 2, 1e-3));
  // Vertex 5 leaves the input, vertex 7 joins: 5 decays, 7 rises, 2 holds.
  enrichment::SurfaceEnrichment next{{2, 7}, Eigen::Matrix3Xd::Constant(3, 2, 1e-3)};
  filter.filter(next, dt, 10);
  ASSERT_EQ(next.vertices, (std::vector<int>{2, 5, 7}));
  EXPECT_NEAR(next.displacements(0, 0), 1e-3, 1e-15);
  EXPECT_NEAR(next.displacements(0, 1), 1e-3 * (1.0 - alpha), 1e-15);
  EXPECT_NEAR(next.displacements(0, 2), 1e-3 * alpha, 1e-15);
  // Nothing in: everything fades, and leaves the field once below the floor.
  int frames = 0;
  for (enrichment::SurfaceEnrichment empty; frames < 1000; ++frames) {
    empty = enrichment::SurfaceEnrichment{{}, Eigen::Matrix3Xd(3, 0)};
    filter.filter(empty, dt, 10);
    if (empty.vertices.empty()) break;
    EXPECT_TRUE(empty.displacements.allFinite());
  }
  EXPECT_NEAR(frames, std::log(1e-9 / (std::sqrt(3.0) * 1e-3)) / std::log(1.0 - alpha), 2.0);
  // Stamps going backwards restart it: the input passes unchanged.
  enrichment::SurfaceEnrichment again{{3}, Eigen::Matrix3Xd::Constant(3, 1, 2e-3)};
  filter.filter(again, -dt, 10);
  EXPECT_EQ(again.displacements, Eigen::Matrix3Xd::Constant(3, 1, 2e-3));
  // Off passes everything through.
  filter.setTimeConstant(0.0);
  enrichment::SurfaceEnrichment passed{{4}, Eigen::Matrix3Xd::Constant(3, 1, 3e-3)};
  filter.filter(passed, dt, 10);
  filter.filter(passed, dt, 10);
  EXPECT_EQ(passed.displacements, Eigen::Matrix3Xd::Constant(3, 1, 3e-3));
  EXPECT_THROW(filter.setTimeConstant(-1.0), InvalidInputError);
  EXPECT_THROW(enrichment::TemporalFilter(std::nan("")), InvalidInputError);
}
