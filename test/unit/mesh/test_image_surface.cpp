#include <gtest/gtest.h>

#include <Eigen/LU>
#include <cmath>
#include <cstdlib>
#include <string>

#include "cgal_data.hpp"
#include "../missing_input.hpp"
#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/barycentric_embedding.hpp"
#include "deformation_enrichment/mesh/image_surface.hpp"
#include "deformation_enrichment/mesh/label_image.hpp"
#include "deformation_enrichment/mesh/surface_report.hpp"
#include "deformation_enrichment/mesh/tetrahedralisation.hpp"

using namespace deformation_enrichment;

namespace {

/// A ball of radius 12 voxels (label 3) in a 40^3 image of 1 x 1 x 2 mm voxels: an ellipsoid in voxels.
mesh::LabelImage ball() {
  mesh::LabelImage image;
  image.size << 40, 40, 20;
  image.spacing << 1e-3, 1e-3, 2e-3;
  image.labels.assign(40 * 40 * 20, 0);
  for (int z = 0; z < 20; ++z)
    for (int y = 0; y < 40; ++y)
      for (int x = 0; x < 40; ++x) {
        const Eigen::Vector3d p((x - 19.5) * 1e-3, (y - 19.5) * 1e-3, (z - 9.5) * 2e-3);
        if (p.norm() < 0.012) image.labels[size_t(x + 40 * (y + 40 * z))] = 3;
      }
  return image;
}

}  // namespace

TEST(ImageSurface, BallOfAnisotropicVoxelsGivesAClosedOutwardSphere) {
  mesh::ImageSurfaceOptions options;
  options.targetVertices = 800;
  const mesh::TriangleMesh sphere = mesh::imageSurface(ball(), options);
  EXPECT_TRUE(mesh::inspectSurface(sphere).closedManifold());
  EXPECT_NEAR(double(sphere.numVertices()), 800.0, 80.0);
  const double exact = 4.0 / 3.0 * M_PI * std::pow(0.012, 3);
  EXPECT_NEAR(mesh::enclosedVolume(sphere), exact, 0.05 * exact);  // outward and about the right size
  const Eigen::Vector3d centre(0.0195, 0.0195, 0.019);
  for (Eigen::Index v = 0; v < sphere.numVertices(); ++v)
    EXPECT_NEAR((sphere.vertices.col(v) - centre).norm(), 0.012, 0.0015) << v;
  options.minLabel = 4;  // no voxel has label 4
  EXPECT_THROW(mesh::imageSurface(ball(), options), InvalidInputError);
  options.minLabel = 1;
  options.isoValue = 1.0;
  EXPECT_THROW(mesh::imageSurface(ball(), options), InvalidInputError);
  EXPECT_THROW(mesh::readLabelImage("/nonexistent/liver.inr.gz"), IoError);
}

TEST(ImageSurface, CgalLiverGivesADisplaySurfaceAndAnEnclosingCoarseVolume) {
  DE_REQUIRE_CGAL_DATA();
  const mesh::LabelImage liver = mesh::readLabelImage(test::CgalData::dir() + "data/images/liver.inr.gz");
  ASSERT_EQ(liver.size, Eigen::Vector3i(438, 353, 165));
  EXPECT_NEAR(liver.spacing.z(), 1.33333e-3, 1e-8);
  long voxels = 0;
  for (const auto label : liver.labels) voxels += label > 0;
  mesh::ImageSurfaceOptions options;
  options.targetVertices = 5000;
  const mesh::TriangleMesh display = mesh::imageSurface(liver, options);
  EXPECT_NEAR(double(display.numVertices()), 5000.0, 500.0);
  const double voxelVolume = double(voxels) * liver.spacing.prod();  // 1.77 litres
  EXPECT_NEAR(mesh::enclosedVolume(display), voxelVolume, 0.05 * voxelVolume);
  if (std::system("command -v tetgen > /dev/null") != 0) DE_MISSING_INPUT("Debian's tetgen is not installed");
  const mesh::Tetrahedralisation fine = mesh::tetrahedralise(display);  // the display surface conforms
  EXPECT_EQ(fine.mesh.vertices.leftCols(display.numVertices()), display.vertices);
  const mesh::CoarseVolume coarse = mesh::coarseVolume(display);
  EXPECT_GE(coarse.volume.mesh.numVertices(), 300);
  EXPECT_LE(coarse.volume.mesh.numVertices(), 1500);
  EXPECT_GT(coarse.inflation, 0.0);
  const mesh::BarycentricEmbedding embedding = mesh::embedPoints(coarse.volume.mesh, display.vertices, 0.02);
  std::printf("liver: %ld display vertices, coarse %ld nodes %ld tets, inflation %.4f m; %s\n", long(display.numVertices()),
              long(coarse.volume.mesh.numVertices()), long(coarse.volume.mesh.numTets()), coarse.inflation,
              mesh::describe(embedding.report, display.numVertices()).c_str());
  EXPECT_LT(embedding.report.outside, display.numVertices() / 5);  // most of the surface is enclosed
  EXPECT_LT(embedding.report.maxDistance, 0.01);
}
