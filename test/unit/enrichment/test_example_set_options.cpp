// optionsFor(set): a set is described at run time exactly as it was acquired, whatever its quadrature.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "deformation_enrichment/enrichment/contact_enricher.hpp"
#include "deformation_enrichment/enrichment/example_set_options.hpp"
#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/grid_tet_mesh.hpp"
#include "deformation_enrichment/mesh/tet_surface.hpp"

using namespace deformation_enrichment;

namespace {

mesh::TriangleMesh coarseSlabSurface() {
  return mesh::extractSurface(mesh::gridTetMesh(Eigen::Vector3d(-0.05, -0.05, 0.0), Eigen::Vector3d(0.05, 0.05, 0.02),
                                                Eigen::Vector3i(12, 12, 3)))
      .surface;
}

// The scene an acquisition run describes its examples with; none of its descriptor options is the default.
scene_file::SceneDescription acquisitionScene(descriptors::Quadrature quadrature) {
  scene_file::SceneDescription s;
  s.name = "test";
  s.procedural = scene_file::Procedural{};
  s.material = {1e4, 0.45};
  s.descriptors.windowScale = 0.007;
  s.descriptors.cutoff = 3.5;
  s.descriptors.averageQuadrature = quadrature == descriptors::Quadrature::Average;
  s.descriptors.sampleSpacing = 0.0025;
  s.stamp.radius = 0.018;
  return s;
}

// The enricher options acquisition uses for that scene, with lower orders than the defaults.
enrichment::ContactEnricherOptions acquisitionOptions(descriptors::Quadrature quadrature) {
  enrichment::ContactEnricherOptions o = enrichment::optionsFor(acquisitionScene(quadrature));
  o.descriptors.siteOrder = 2;
  o.descriptors.deformationOrder = 1;
  return o;
}

Eigen::Matrix3Xd acquisitionDent(const Eigen::Matrix3Xd& rest) {
  Eigen::Matrix3Xd current = rest;
  for (Eigen::Index v = 0; v < rest.cols(); ++v) {
    const double g = std::exp(-(rest.col(v) - Eigen::Vector3d(0.004, -0.002, 0.02)).squaredNorm() / (2.0 * 0.008 * 0.008));
    current.col(v) += g * Eigen::Vector3d(0.001, 0.0, -0.002);
  }
  return current;
}

// The set acquisition writes: one example described with the scene's options, its provenance.
examples::ExampleSet acquiredSet(descriptors::Quadrature quadrature, const mesh::TriangleMesh& rest,
                                 const enrichment::Contact& contact) {
  const enrichment::ContactEnricherOptions options = acquisitionOptions(quadrature);
  const enrichment::ContactEnricher acquisition(rest, options);
  const enrichment::ContactDescription d = acquisition.describe(acquisitionDent(rest.vertices), contact);
  examples::Example e;
  e.contact = d.p;
  e.frame = d.B;
  e.rho = d.rho;
  e.mu = d.mu;
  e.stamp = cv::Mat(4, 4, CV_32FC3, cv::Scalar::all(0.0));
  e.stampRadius = options.stampRadius;
  examples::ExampleSet set;
  set.metadata.provenance = examples::Provenance{acquisitionScene(quadrature), {}, {}};
  set.examples.push_back(e);
  return set;
}

}  // namespace

TEST(ExampleSetOptions, EachQuadratureIsDescribedAtRunTimeExactlyAsAcquired) {
  const mesh::TriangleMesh rest = coarseSlabSurface();
  enrichment::Contact contact;
  contact.point = Eigen::Vector3d(0.004, -0.002, 0.02);
  for (const auto quadrature : {descriptors::Quadrature::Volume, descriptors::Quadrature::Average}) {
    SCOPED_TRACE(quadrature == descriptors::Quadrature::Volume ? "volume" : "average");
    const enrichment::ContactEnricherOptions acquired = acquisitionOptions(quadrature);
    const examples::ExampleSet set = acquiredSet(quadrature, rest, contact);
    const enrichment::ContactEnricherOptions runTime = enrichment::optionsFor(set);
    EXPECT_EQ(runTime.descriptors.window.quadrature, quadrature);
    EXPECT_EQ(runTime.descriptors.window.scale, acquired.descriptors.window.scale);
    EXPECT_EQ(runTime.descriptors.window.cutoff, acquired.descriptors.window.cutoff);
    EXPECT_EQ(runTime.sampleSpacing, acquired.sampleSpacing);
    EXPECT_EQ(runTime.stampRadius, acquired.stampRadius);
    EXPECT_EQ(runTime.descriptors.siteOrder, 2);
    EXPECT_EQ(runTime.descriptors.deformationOrder, 1);
    // The run-time enricher describes the acquired contact with the example's own descriptors, bit for bit.
    const enrichment::ContactDescription d = enrichment::ContactEnricher(rest, runTime).describe(acquisitionDent(rest.vertices), contact);
    const examples::Example& e = set.examples.front();
    ASSERT_EQ(d.rho.values().size(), e.rho.values().size());
    ASSERT_EQ(d.mu.values().size(), e.mu.values().size());
    EXPECT_EQ(d.rho.values(), e.rho.values());
    EXPECT_EQ(d.mu.values(), e.mu.values());
    EXPECT_EQ(d.B, e.frame);
  }
  // The two quadratures really describe the contact differently (or the test above would prove nothing).
  const examples::ExampleSet volume = acquiredSet(descriptors::Quadrature::Volume, rest, contact);
  const examples::ExampleSet average = acquiredSet(descriptors::Quadrature::Average, rest, contact);
  EXPECT_GT((volume.examples.front().rho.values() - average.examples.front().rho.values()).norm(), 0.0);
}

TEST(ExampleSetOptions, SetsWithoutProvenanceUseTheirMetadataAndBadValuesAreRefused) {
  const mesh::TriangleMesh rest = coarseSlabSurface();
  enrichment::Contact contact;
  contact.point = Eigen::Vector3d(0.0, 0.0, 0.02);
  // A set without provenance: named entries, the cut-off not among them.
  examples::ExampleSet set = acquiredSet(descriptors::Quadrature::Average, rest, contact);
  set.metadata.provenance.reset();
  set.metadata.material = {{"window_scale_m", 0.007}, {"site_sample_spacing_m", 0.0025}, {"average_quadrature", 1.0}};
  enrichment::ContactEnricherOptions defaults;
  defaults.descriptors.window.cutoff = 4.5;
  defaults.rimBand = 0.3;  // run-time knob: kept
  const enrichment::ContactEnricherOptions o = enrichment::optionsFor(set, defaults);
  EXPECT_EQ(o.descriptors.window.cutoff, 4.5);
  EXPECT_EQ(o.rimBand, 0.3);
  EXPECT_EQ(o.descriptors.window.scale, 0.007);
  EXPECT_EQ(o.descriptors.window.quadrature, descriptors::Quadrature::Average);
  EXPECT_EQ(o.stampRadius, 0.018);

  for (const double bad : {0.0, -0.01, std::numeric_limits<double>::quiet_NaN()}) {
    examples::ExampleSet broken = set;
    broken.metadata.material["window_scale_m"] = bad;
    EXPECT_THROW(enrichment::optionsFor(broken), InvalidInputError);
  }
  examples::ExampleSet mixed = set;
  mixed.examples.push_back(set.examples.front());
  mixed.examples.back().stampRadius = 0.02;
  EXPECT_THROW(enrichment::optionsFor(mixed), InvalidInputError);
  EXPECT_THROW(enrichment::optionsFor(examples::ExampleSet{}), InvalidInputError);
}
