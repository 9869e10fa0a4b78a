// The Hermite order knob: truncating an order-N deformation descriptor gives the order-M descriptor
// (M < N) the run time computes, so a set built with order N runs at M; the kernel-width knob restores
// the loaded widths on 0.
#include <gtest/gtest.h>

#include <cmath>

#include "deformation_enrichment/enrichment/contact_enricher.hpp"
#include "deformation_enrichment/enrichment/descriptor_order.hpp"
#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/grid_tet_mesh.hpp"
#include "deformation_enrichment/mesh/tet_surface.hpp"

using namespace deformation_enrichment;

namespace {

mesh::TriangleMesh slab() {
  return mesh::extractSurface(mesh::gridTetMesh(Eigen::Vector3d(-0.05, -0.05, 0.0), Eigen::Vector3d(0.05, 0.05, 0.02),
                                                Eigen::Vector3i(12, 12, 2)))
      .surface;
}

enrichment::ContactEnricherOptions options(int order) {
  enrichment::ContactEnricherOptions o;
  o.descriptors.window.scale = 0.008;
  o.descriptors.deformationOrder = order;
  o.stampRadius = 0.02;
  o.sampleSpacing = 0.004;
  return o;
}

// A sheared dent around the top centre (smooth, so every order of mu is non-zero).
Eigen::Matrix3Xd shearedDent(const Eigen::Matrix3Xd& rest) {
  Eigen::Matrix3Xd current = rest;
  for (Eigen::Index v = 0; v < rest.cols(); ++v) {
    const Eigen::Vector3d d = rest.col(v) - Eigen::Vector3d(0.001, 0.0, 0.02);
    const double g = std::exp(-d.squaredNorm() / (2.0 * 0.008 * 0.008));
    current.col(v) += g * Eigen::Vector3d(0.002 + 0.1 * d.x() * d.x(), 0.0005, -0.003 + 0.2 * d.x() * d.y());
  }
  return current;
}

examples::ExampleSet setOf(const std::vector<enrichment::ContactDescription>& descriptions) {
  examples::ExampleSet set;
  for (const auto& d : descriptions) {
    examples::Example e;
    e.contact = d.p;
    e.frame = d.B;
    e.rho = d.rho;
    e.mu = d.mu;
    e.stamp = cv::Mat(8, 8, CV_32FC3, cv::Scalar(0.0f, 0.0f, -0.001f * static_cast<float>(set.examples.size() + 1)));
    e.stampRadius = 0.02;
    set.examples.push_back(e);
  }
  return set;
}

}  // namespace

TEST(DescriptorOrder, TruncatedOrderThreeDescriptorEqualsTheOrderTwoDescriptor) {
  const mesh::TriangleMesh rest = slab();
  const Eigen::Matrix3Xd current = shearedDent(rest.vertices);
  enrichment::Contact contact;
  contact.point = Eigen::Vector3d(0.0, 0.0, 0.02);
  const auto three = enrichment::ContactEnricher(rest, options(3)).describe(current, contact);
  const auto two = enrichment::ContactEnricher(rest, options(2)).describe(current, contact);
  ASSERT_EQ(three.mu.lastOrder(), 3);
  ASSERT_GT(three.mu.order(3, 0).norm() + three.mu.order(3, 2).norm(), 0.0) << "order 3 must carry something to drop";
  EXPECT_TRUE(three.B.isApprox(two.B, 1e-12)) << "same stamping frame at both orders";
  const hermite::MomentList truncated = enrichment::truncatedMoments(three.mu, 2);
  ASSERT_EQ(truncated.firstOrder(), two.mu.firstOrder());
  ASSERT_EQ(truncated.lastOrder(), two.mu.lastOrder());
  ASSERT_EQ(truncated.channels(), two.mu.channels());
  EXPECT_LT((truncated.values() - two.mu.values()).norm(), 1e-12 * (1.0 + two.mu.values().norm()));
  for (int c = 0; c < 3; ++c)
    for (int n = 1; n <= 2; ++n) EXPECT_EQ(truncated.order(n, c), three.mu.order(n, c));
}

TEST(DescriptorOrder, SetsTruncateDownAndRefuseUp) {
  const mesh::TriangleMesh rest = slab();
  const Eigen::Matrix3Xd current = shearedDent(rest.vertices);
  const enrichment::ContactEnricher describer(rest, options(3));
  enrichment::Contact a, b;
  a.point = Eigen::Vector3d(0.0, 0.0, 0.02);
  b.point = Eigen::Vector3d(0.01, 0.0, 0.02);
  const examples::ExampleSet set = setOf({describer.describe(current, a), describer.describe(current, b)});
  EXPECT_EQ(enrichment::deformationOrder(set), 3);
  const examples::ExampleSet one = enrichment::withDeformationOrder(set, 1);
  EXPECT_EQ(enrichment::deformationOrder(one), 1);
  EXPECT_EQ(one.examples[1].mu.order(1, 2), set.examples[1].mu.order(1, 2));
  EXPECT_EQ(one.examples[0].rho.values(), set.examples[0].rho.values()) << "rho is untouched";
  try {
    enrichment::withDeformationOrder(set, 4);
    ADD_FAILURE() << "order 4 of an order-3 set must be refused";
  } catch (const InvalidInputError& e) {
    EXPECT_NE(std::string(e.what()).find("stores mu orders 1..3"), std::string::npos) << e.what();
  }
  EXPECT_THROW(enrichment::withDeformationOrder(set, 0), InvalidInputError);
  EXPECT_THROW(enrichment::truncatedMoments(set.examples[0].mu, 0), InvalidInputError);
  examples::ExampleSet mixed = set;
  mixed.examples[1].mu = one.examples[1].mu;
  EXPECT_THROW(enrichment::deformationOrder(mixed), InvalidInputError);
  EXPECT_THROW(enrichment::deformationOrder(examples::ExampleSet()), InvalidInputError);

  // The truncated set runs on an order-2 enricher: both sides compare mu_1..mu_2.
  enrichment::ContactEnricher enricher(rest, options(2));
  enricher.setExamples(enrichment::withDeformationOrder(set, 2));
  enrichment::EnrichmentResult result;
  enricher.enrich(current, {a}, result);
  ASSERT_EQ(result.contacts.size(), 1u);
  EXPECT_NEAR(result.contacts[0].confidence, 1.0, 1e-9) << "the example's own contact at the truncated order";
  EXPECT_FALSE(result.enrichment.vertices.empty());
}

TEST(DescriptorOrder, KernelWidthKnobReplacesAndRestoresTheLoadedWidths) {
  const mesh::TriangleMesh rest = slab();
  const Eigen::Matrix3Xd current = shearedDent(rest.vertices);
  enrichment::ContactEnricher enricher(rest, options(2));
  EXPECT_THROW(enricher.setKernelWidths(0.1, 0.1), InvalidInputError) << "no set loaded";
  enrichment::Contact a, b;
  a.point = Eigen::Vector3d(0.0, 0.0, 0.02);
  b.point = Eigen::Vector3d(0.01, 0.0, 0.02);
  enricher.setExamples(setOf({enricher.describe(current, a), enricher.describe(current, b)}));
  const enrichment::KernelWidths loaded = enricher.blender()->widths();
  EXPECT_EQ(enricher.loadedWidths().sigmaRho, loaded.sigmaRho);
  EXPECT_EQ(enricher.loadedWidths().sigmaU, loaded.sigmaU);
  enricher.setKernelWidths(0.0, 0.25);
  EXPECT_EQ(enricher.blender()->widths().sigmaRho, loaded.sigmaRho) << "0 keeps the loaded width";
  EXPECT_EQ(enricher.blender()->widths().sigmaU, 0.25);
  EXPECT_THROW(enricher.setKernelWidths(std::nan(""), 0.1), InvalidInputError);
  EXPECT_EQ(enricher.blender()->widths().sigmaU, 0.25) << "a refused width leaves the old ones";
  enricher.setKernelWidths(-1.0, 0.0);
  EXPECT_EQ(enricher.blender()->widths().sigmaRho, loaded.sigmaRho);
  EXPECT_EQ(enricher.blender()->widths().sigmaU, loaded.sigmaU);
}
