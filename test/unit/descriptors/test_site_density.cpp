// Where rho's density comes from for open and closed surfaces (descriptors/site_density.hpp): the shell under
// an open surface, the volume around it, and the choice Auto makes, with the reasons it gives.
#include <gtest/gtest.h>

#include "../top_face.hpp"

#include <set>
#include <tuple>

#include "deformation_enrichment/descriptors/interior_sampling.hpp"
#include "deformation_enrichment/descriptors/shell_sampling.hpp"
#include "deformation_enrichment/descriptors/site_density.hpp"
#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/grid_tet_mesh.hpp"
#include "deformation_enrichment/mesh/tet_surface.hpp"

using namespace deformation_enrichment;
using descriptors::SiteDensitySource;

namespace {

// The 10 x 10 x 2 cm slab as a tet grid, its closed boundary, and that boundary's top face alone (open).
mesh::TetMesh slabVolume() {
  return mesh::gridTetMesh(Eigen::Vector3d(-0.05, -0.05, 0.0), Eigen::Vector3d(0.05, 0.05, 0.02), Eigen::Vector3i(10, 10, 2));
}


std::set<std::tuple<long, long, long>> keys(const descriptors::PointSampling& s) {
  std::set<std::tuple<long, long, long>> out;  // positions to 1 um: the same grid gives the same keys
  for (Eigen::Index m = 0; m < s.size(); ++m)
    out.emplace(std::lround(s.points()(0, m) * 1e6), std::lround(s.points()(1, m) * 1e6), std::lround(s.points()(2, m) * 1e6));
  return out;
}

}  // namespace

TEST(ShellSampling, AShellAsDeepAsTheSlabIsItsInteriorAndStopsAtTheRim) {
  const mesh::TriangleMesh closed = mesh::extractSurface(slabVolume()).surface;
  const mesh::TriangleMesh open = de_test::topFace(closed, 0.02);
  const double spacing = 0.0021;
  const auto interior = keys(descriptors::sampleClosedSurfaceInterior(closed, spacing));
  // 2 cm deep: everything under the top face down to the bottom, nothing beside the rim.
  const descriptors::PointSampling shell = descriptors::sampleShellUnderSurface(open, 0.02, spacing);
  const auto shellKeys = keys(shell);
  EXPECT_EQ(shellKeys, interior) << "the same grid, the same cells: " << shellKeys.size() << " vs " << interior.size();
  EXPECT_NEAR(shell.volumes().sum(), 0.1 * 0.1 * 0.02, 0.1 * 0.1 * spacing) << "the slab's volume";
  // 5 mm deep: the top layer only, all of it inside the slab.
  const descriptors::PointSampling thin = descriptors::sampleShellUnderSurface(open, 0.005, spacing);
  EXPECT_NEAR(thin.volumes().sum(), 0.1 * 0.1 * 0.005, 0.1 * 0.1 * spacing);
  for (Eigen::Index m = 0; m < thin.size(); ++m) {
    EXPECT_GE(thin.points()(2, m), 0.015 - 1e-9);
    EXPECT_LE(thin.points().col(m).head<2>().cwiseAbs().maxCoeff(), 0.05);
  }
  EXPECT_THROW(descriptors::sampleShellUnderSurface(open, 0.0, spacing), InvalidInputError);
  EXPECT_THROW(descriptors::sampleShellUnderSurface(open, 0.005, -1.0), InvalidInputError);
  EXPECT_THROW(descriptors::sampleShellUnderSurface(open, 0.005, 1e-5, 1000), InvalidInputError);
}

TEST(SiteDensity, AutoTakesTheInteriorOfAClosedSurfaceTheVolumeOfAnOpenOneElseAShell) {
  const mesh::TetMesh volume = slabVolume();
  const mesh::TriangleMesh closed = mesh::extractSurface(volume).surface;
  const mesh::TriangleMesh open = de_test::topFace(closed, 0.02);
  descriptors::SiteDensityOptions o;
  o.spacing = 0.0021;
  o.shellThickness = 0.006;
  const descriptors::SiteDensity fromClosed = descriptors::siteDensity(closed, &volume, o);
  EXPECT_EQ(fromClosed.source, SiteDensitySource::Surface) << "acquisition samples the closed surface: so does the run time";
  const descriptors::SiteDensity fromVolume = descriptors::siteDensity(open, &volume, o);
  EXPECT_EQ(fromVolume.source, SiteDensitySource::Volume) << fromVolume.description;
  EXPECT_EQ(keys(fromVolume.sampling), keys(fromClosed.sampling)) << "the volume fills what the closed surface encloses";
  const descriptors::SiteDensity fromShell = descriptors::siteDensity(open, nullptr, o);
  EXPECT_EQ(fromShell.source, SiteDensitySource::Shell);
  EXPECT_NE(fromShell.description.find("no volume"), std::string::npos) << fromShell.description;
  EXPECT_NEAR(fromShell.sampling.volumes().sum(), 0.1 * 0.1 * 0.006, 0.1 * 0.1 * o.spacing);

  // A volume that does not hold the surface (moved 5 cm aside): Auto says why and takes the shell; asked
  // for explicitly, the volume is refused with how many vertices lie how far out.
  mesh::TetMesh aside = volume;
  aside.vertices.row(0).array() += 0.05;
  const descriptors::SiteDensity fallback = descriptors::siteDensity(open, &aside, o);
  EXPECT_EQ(fallback.source, SiteDensitySource::Shell);
  EXPECT_NE(fallback.description.find("the volume was refused"), std::string::npos) << fallback.description;
  o.source = SiteDensitySource::Volume;
  try {
    descriptors::siteDensity(open, &aside, o);
    ADD_FAILURE() << "a volume 5 cm aside was accepted";
  } catch (const InvalidInputError& e) {
    EXPECT_NE(std::string(e.what()).find("farther than"), std::string::npos) << e.what();
  }
  o.source = SiteDensitySource::Surface;
  EXPECT_THROW(descriptors::siteDensity(open, &volume, o), InvalidInputError) << "an open surface has no interior";
  EXPECT_EQ(descriptors::parseSiteDensitySource("shell"), SiteDensitySource::Shell);
  EXPECT_THROW(descriptors::parseSiteDensitySource("inside"), InvalidInputError);
}
