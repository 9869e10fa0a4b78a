#include <gtest/gtest.h>

#include "enricher_test_support.hpp"

#include <cmath>
#include <cstring>
#include <limits>

#include "deformation_enrichment/enrichment/contact_enricher.hpp"
#include "deformation_enrichment/enrichment/stamp.hpp"
#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/grid_tet_mesh.hpp"
#include "deformation_enrichment/mesh/tet_surface.hpp"

using namespace deformation_enrichment;
using enrichment::Contact;
using enrichment::ContactEnricher;

namespace {

using de_test::slabSurface;
enrichment::ContactEnricherOptions options() { return de_test::enricherOptions(); }

using de_test::dented;
using de_test::oneExampleSet;
using de_test::syntheticStamp;

enrichment::ExampleBlenderOptions fixedWidths() {
  enrichment::ExampleBlenderOptions b;
  b.fitWidths = false;
  b.widths.sigmaRho = 0.05;
  b.widths.sigmaU = 0.3;
  return b;
}

Contact restContact(const Eigen::Vector3d& p) {
  Contact c;
  c.point = p;
  return c;
}

}  // namespace

TEST(ContactEnricher, AMovedEnricherEnrichesAsBefore) {
  // Its KD-trees refer to its rest vertices: a move must leave them valid (the session moves enrichers).
  ContactEnricher original(slabSurface(), options());
  const Eigen::Vector3d p(0.001, -0.002, 0.02);
  const Eigen::Matrix3Xd current = dented(original.restSurface().vertices, p, 1.0);
  const Contact contact{p, true, std::nullopt, 0, std::nullopt, 0.0};
  original.setExamples(oneExampleSet(original.describe(current, contact), syntheticStamp(32, 0.02), 0.02), fixedWidths());
  enrichment::EnrichmentResult before, after;
  original.enrich(current, {contact}, before);
  ContactEnricher moved(std::move(original));
  ContactEnricher assigned(slabSurface(), options());
  assigned = std::move(moved);
  assigned.enrich(current, {contact}, after);
  ASSERT_FALSE(before.enrichment.vertices.empty());
  EXPECT_EQ(after.enrichment.vertices, before.enrichment.vertices);
  EXPECT_TRUE(after.enrichment.displacements == before.enrichment.displacements);
}

TEST(ContactEnricher, OneExampleReproducesItsStampAtItsOwnContact) {
  ContactEnricher enricher(slabSurface(), options());
  const Eigen::Matrix3Xd& rest = enricher.restSurface().vertices;
  const Eigen::Vector3d p(0.001, -0.002, 0.02);
  const Eigen::Matrix3Xd current = dented(rest, p, 1.0);
  const Contact contact{p, true, std::nullopt, 3, std::nullopt, 0.0};
  const enrichment::ContactDescription d = enricher.describe(current, contact);
  EXPECT_NEAR((d.B.transpose() * d.B - Eigen::Matrix3d::Identity()).norm(), 0.0, 1e-12);
  EXPECT_GT(d.B.col(2).z(), 0.99);  // b_z = outward normal of the top face
  EXPECT_GT(d.mu.values().norm(), 0.0);
  const cv::Mat stamp = syntheticStamp(48, 0.02);
  enricher.setExamples(oneExampleSet(d, stamp, 0.02), fixedWidths());

  enrichment::EnrichmentResult result;
  enricher.enrich(current, {contact}, result);
  ASSERT_EQ(result.contacts.size(), 1u);
  EXPECT_EQ(result.contacts[0].toolId, 3);
  EXPECT_NEAR(result.contacts[0].confidence, 1.0, 1e-9);
  EXPECT_NEAR(result.contacts[0].weights(0), 1.0, 1e-5);
  ASSERT_FALSE(result.enrichment.vertices.empty());
  const double inner = (1.0 - enricher.options().rimBand) * 0.02;
  int checked = 0;
  for (std::size_t i = 0; i < result.enrichment.vertices.size(); ++i) {
    const int v = result.enrichment.vertices[i];
    const Eigen::Vector3d x = rest.col(v);
    EXPECT_LE((x - p).norm(), 0.02 + 1e-12);
    if ((x - p).norm() > inner) continue;
    const Eigen::Vector2d s = (d.B.leftCols<2>().transpose() * (x - p));
    // eq. (1): e = R B Psi(phi, varphi) with the example's own stamp
    const Eigen::Vector3d expected = d.R * d.B * enrichment::sampleStamp(stamp, 0.02, s.x(), s.y());
    EXPECT_LT((result.enrichment.displacements.col(static_cast<Eigen::Index>(i)) - expected).norm(), 1e-5 * 1e-3 + 1e-9);
    ++checked;
  }
  EXPECT_GT(checked, 10);
  // Untouched vertices keep their bits.
  Eigen::Matrix3Xd state = current;
  enricher.apply(result, state);
  std::vector<bool> touched(static_cast<std::size_t>(rest.cols()), false);
  for (int v : result.enrichment.vertices) touched[static_cast<std::size_t>(v)] = true;
  for (Eigen::Index v = 0; v < rest.cols(); ++v)
    if (!touched[static_cast<std::size_t>(v)]) {
      EXPECT_EQ(std::memcmp(state.col(v).data(), current.col(v).data(), 3 * sizeof(double)), 0);
    }
  EXPECT_GE(result.timings.totalSeconds, result.timings.mapSeconds);
}

TEST(ContactEnricher, UnlikeContactGetsNoDetail) {
  ContactEnricher enricher(slabSurface(), options());
  const Eigen::Matrix3Xd& rest = enricher.restSurface().vertices;
  const Eigen::Vector3d p(0.0, 0.0, 0.02);
  const Contact contact{p, true, std::nullopt, 0, std::nullopt, 0.0};
  const enrichment::ContactDescription d = enricher.describe(dented(rest, p, 1.0), contact);
  enricher.setExamples(oneExampleSet(d, syntheticStamp(32, 0.02), 0.02), fixedWidths());
  enrichment::EnrichmentResult result;
  // Same site, opposite deformation (pulled out instead of pressed in): mu anti-correlated.
  enricher.enrich(dented(rest, p, -1.0), {contact}, result);
  EXPECT_LT(result.contacts[0].confidence, 1e-3);
  EXPECT_LT(result.enrichment.displacements.cwiseAbs().maxCoeff(), 1e-3 * 1e-3);
  // Far away near a corner (different site), deformed there the same way.
  const Eigen::Vector3d q(0.046, 0.046, 0.02);
  enricher.enrich(dented(rest, q, 1.0), {Contact{q, true, std::nullopt, 0, std::nullopt, 0.0}}, result);
  EXPECT_LT(result.contacts[0].confidence, 1e-3) << "d_rho " << enricher.describe(dented(rest, q, 1.0), restContact(q)).rho.values().transpose();
  EXPECT_LT(result.enrichment.displacements.cwiseAbs().maxCoeff(), 1e-3 * 1e-3);
}

TEST(ContactEnricher, CurrentStateContactAtAVertexMapsToThatVertex) {
  ContactEnricher enricher(slabSurface(), options());
  const Eigen::Matrix3Xd& rest = enricher.restSurface().vertices;
  const Eigen::Vector3d p(0.0, 0.0, 0.02);
  const Eigen::Matrix3Xd current = dented(rest, p, 1.0);
  const auto byRest = enricher.describe(current, Contact{p, true, std::nullopt, 0, std::nullopt, 0.0});
  const auto byCurrent = enricher.describe(current, Contact{current.col(byRest.vertex), false, std::nullopt, 0, std::nullopt, 0.0});
  EXPECT_EQ(byCurrent.vertex, byRest.vertex);
  EXPECT_LT((byCurrent.mu.values() - byRest.mu.values()).norm(), 1e-9 + 1e-6 * byRest.mu.values().norm());
}

TEST(ContactEnricher, BadInputThrowsTypedErrors) {
  ContactEnricher enricher(slabSurface(), options());
  const Eigen::Matrix3Xd rest = enricher.restSurface().vertices;
  enrichment::EnrichmentResult result;
  enricher.enrich(rest, {}, result);  // no contact: no work, no examples needed
  EXPECT_TRUE(result.enrichment.vertices.empty());
  EXPECT_THROW(enricher.enrich(rest, {Contact{}}, result), InvalidInputError);  // no examples loaded
  const Contact contact{Eigen::Vector3d(0, 0, 0.02), true, std::nullopt, 0, std::nullopt, 0.0};
  Eigen::Matrix3Xd bad = rest;
  bad(1, 5) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(enricher.describe(bad, contact), InvalidInputError);
  EXPECT_THROW(enricher.describe(rest.leftCols(3), contact), InvalidInputError);
  EXPECT_THROW(enricher.describe(rest, restContact(Eigen::Vector3d(NAN, 0, 0))), InvalidInputError);
  EXPECT_THROW(enricher.describe(rest, restContact(Eigen::Vector3d(1.0, 1.0, 1.0))), InvalidInputError);  // far off
  // A set whose stamp radius differs is rejected and the enricher keeps having no examples.
  const auto d = enricher.describe(dented(rest, contact.point, 1.0), contact);
  EXPECT_THROW(enricher.setExamples(oneExampleSet(d, syntheticStamp(8, 0.03), 0.03), fixedWidths()), InvalidInputError);
  EXPECT_FALSE(enricher.hasExamples());
  EXPECT_THROW(enricher.setDetailGain({-1.0, 0.0}), InvalidInputError);
  // Open surface: no interior sampling possible.
  mesh::TriangleMesh open = slabSurface();
  open.triangles.conservativeResize(3, open.triangles.cols() - 1);
  EXPECT_THROW(ContactEnricher(open, options()), InvalidInputError);
  auto o = options();
  o.stampRadius = 0.0;
  EXPECT_THROW(ContactEnricher(slabSurface(), o), InvalidInputError);
}

TEST(ContactEnricher, MagnitudeAwareStampScalesWithMu) {
  auto o = options();
  o.magnitudeAware = true;
  o.maxMagnitudeRatio = std::numeric_limits<double>::infinity();  // the bound has its own test
  ContactEnricher enricher(slabSurface(), o);
  const Eigen::Matrix3Xd& rest = enricher.restSurface().vertices;
  const Eigen::Vector3d p(0.0, 0.001, 0.02);
  const Contact contact = restContact(p);
  const auto d1 = enricher.describe(dented(rest, p, 1.0), contact);
  const cv::Mat stamp = syntheticStamp(32, 0.02);
  enricher.setExamples(oneExampleSet(d1, stamp, 0.02), fixedWidths());
  const Eigen::Matrix3Xd twice = dented(rest, p, 2.0);
  const auto d2 = enricher.describe(twice, contact);
  const double scale = d2.mu.values().norm() / d1.mu.values().norm();
  EXPECT_GT(scale, 1.5);  // a twice as strong dent: mu about twice as large
  enrichment::EnrichmentResult result;
  enricher.enrich(twice, {contact}, result);
  const double w = result.contacts[0].weights(0);
  EXPECT_GT(w, 0.5);
  int checked = 0;
  for (std::size_t i = 0; i < result.enrichment.vertices.size(); ++i) {
    const Eigen::Vector3d x = rest.col(result.enrichment.vertices[i]);
    if ((x - p).norm() > 0.7 * 0.02) continue;
    const Eigen::Vector2d s = d2.B.leftCols<2>().transpose() * (x - p);
    const Eigen::Vector3d expected = scale * w * d2.R * d2.B * enrichment::sampleStamp(stamp, 0.02, s.x(), s.y());
    EXPECT_LT((result.enrichment.displacements.col(static_cast<Eigen::Index>(i)) - expected).norm(), 1e-7 * 1e-3 + 1e-12);
    ++checked;
  }
  EXPECT_GT(checked, 10);
}

TEST(ContactEnricher, RestPointCachesGiveTheSameEnrichmentAsAFreshEnricher) {
  // Windows and stamp balls are cached per rest point (4 each): after more distinct contacts than that,
  // and again straight after, the result equals a fresh enricher's bit for bit.
  const mesh::TriangleMesh rest = slabSurface();
  enrichment::ContactEnricher reference(rest, options()), reused(rest, options());
  const Eigen::Vector3d p(0.004, -0.003, 0.02);
  const Eigen::Matrix3Xd state = dented(rest.vertices, p, 1.0);
  const auto d = reference.describe(state, restContact(p));
  for (auto* e : {&reference, &reused}) e->setExamples(oneExampleSet(d, syntheticStamp(32, 0.02), 0.02), fixedWidths());
  enrichment::EnrichmentResult expected, got;
  reference.enrich(state, {restContact(p)}, expected);
  ASSERT_FALSE(expected.enrichment.vertices.empty());
  for (int round = 0; round < 2; ++round) {
    for (int k = 0; k < 6; ++k) reused.enrich(state, {restContact(p + Eigen::Vector3d(0.002 * (k - 3), 0.001 * k, 0.0))}, got);
    for (int repeat = 0; repeat < 2; ++repeat) {
      reused.enrich(state, {restContact(p)}, got);
      EXPECT_EQ(got.enrichment.vertices, expected.enrichment.vertices);
      EXPECT_EQ(got.enrichment.displacements, expected.enrichment.displacements);
      EXPECT_EQ(got.contacts.at(0).weights, expected.contacts.at(0).weights);
    }
  }
}
