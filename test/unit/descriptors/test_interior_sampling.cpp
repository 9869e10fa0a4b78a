#include <gtest/gtest.h>

#include <cstdio>
#include <string>
#include <unistd.h>

#include "descriptor_test_support.hpp"
#include "deformation_enrichment/descriptors/evaluator_loading.hpp"
#include "deformation_enrichment/descriptors/interior_sampling.hpp"
#include "deformation_enrichment/descriptors/moment_window.hpp"
#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/mesh_io.hpp"
#include "deformation_enrichment/mesh/tet_surface.hpp"

using namespace deformation_enrichment;
using namespace deformation_enrichment::descriptors;

TEST(InteriorSampling, BoxSurfaceGivesVolumeAndSiteMoments) {
  const Eigen::Vector3d lo(-1, -0.5, -0.25), hi(1, 0.5, 0.25);
  const mesh::TetSurface boundary = mesh::extractSurface(de_test::uniformBox(lo, hi, 4));
  const PointSampling samples = sampleClosedSurfaceInterior(boundary.surface, 0.05);
  EXPECT_NEAR(samples.volumes().sum(), 1.0, 1e-9) << "box volume 2 x 1 x 0.5 (the grid fits the box exactly)";
  WindowOptions options;
  options.scale = 0.2;
  const Eigen::Vector3d p(0.4, 0.5, 0.1);  // on a side face
  const double error =
      de_test::relativeError(densityMoments(gatherWindow(samples, p, options), 0, 3), de_test::boxMoments(lo, hi, p, 0.2, 3));
  std::printf("interior grid h/4: relative error of rho vs exact box moments %.3e\n", error);
  EXPECT_LT(error, 0.05);
}

TEST(InteriorSampling, RejectsOpenSurfacesAndBadSpacing) {
  mesh::TetSurface boundary = mesh::extractSurface(de_test::uniformBox(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(), 2));
  EXPECT_THROW(sampleClosedSurfaceInterior(boundary.surface, 0.0), InvalidInputError);
  EXPECT_THROW(sampleClosedSurfaceInterior(boundary.surface, 1e-4, 1000), InvalidInputError);
  // Remove the triangles of the top face: rays through it cross the surface once.
  mesh::TriangleMesh open = boundary.surface;
  std::vector<int> keep;
  for (Eigen::Index t = 0; t < open.numTriangles(); ++t) {
    bool top = true;
    for (int k = 0; k < 3; ++k) top = top && open.vertices(2, open.triangles(k, t)) > 0.999;
    if (!top) keep.push_back(static_cast<int>(t));
  }
  Eigen::Matrix3Xi triangles(3, keep.size());
  for (std::size_t t = 0; t < keep.size(); ++t) triangles.col(t) = open.triangles.col(keep[t]);
  open.triangles = triangles;
  EXPECT_THROW(sampleClosedSurfaceInterior(open, 0.1), InvalidInputError);
}

TEST(InteriorSampling, ObjInputLoadsAsSiteOnlyEvaluator) {
  char pattern[] = "/tmp/de_interior_XXXXXX";
  const std::string dir = mkdtemp(pattern);
  const Eigen::Vector3d lo(-1, -1, -1), hi(1, 1, 1);
  mesh::writeTriangleMesh(dir + "/cube.obj", mesh::extractSurface(de_test::uniformBox(lo, hi, 3)).surface);
  DescriptorOptions options;
  options.window.scale = 0.3;
  const LoadedObject object = loadDescriptorObject(dir + "/cube.obj", options);
  EXPECT_FALSE(object.volumetric);
  const Eigen::Vector3d p(0.35, -0.2, 1.0);
  const ContactDescriptor contact = object.evaluator.evaluate(p);
  EXPECT_LT(de_test::relativeError(contact.rhoWorld, de_test::boxMoments(lo, hi, p, 0.3, 3)), 0.03);
  EXPECT_GT(contact.normal.z(), 0.999);
  EXPECT_THROW(loadDescriptorObject(dir + "/cube.stl", options), InvalidInputError);
  EXPECT_THROW(loadDescriptorObject(dir + "/missing.node", options), IoError);
  std::remove((dir + "/cube.obj").c_str());
  rmdir(dir.c_str());
}
