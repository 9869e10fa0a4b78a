#pragma once
// Where the site descriptor's density ([Seiler14 eq. 7]: the material's indicator, integrated by eq. 8)
// comes from for one display surface (docs/design.md §6): rho is a property of the volume around the
// contact, not of the surface, so an open surface embedded in a volume is described like a closed one.
//   Surface  the interior of the closed surface itself (what acquisition samples);
//   Volume   the interior of a tet mesh around the surface (the scene's coarse volume);
//   Shell    a shell of `shellThickness` behind an open surface that comes without a volume.
// Auto picks Surface for a closed surface, Volume for an open one with a volume that holds it, Shell
// otherwise. All three sample the same kind of grid at the same spacing, so they agree where their
// material does.
#include <optional>
#include <string>

#include "deformation_enrichment/descriptors/point_sampling.hpp"
#include "deformation_enrichment/mesh/tet_mesh.hpp"
#include "deformation_enrichment/mesh/triangle_mesh.hpp"

namespace deformation_enrichment::descriptors {

enum class SiteDensitySource { Auto, Surface, Volume, Shell };

struct SiteDensityOptions {
  SiteDensitySource source = SiteDensitySource::Auto;
  double spacing = 0.0015;        ///< grid step (m), > 0
  double shellThickness = 0.018;  ///< m, > 0 (the node's default: 3 window scales, where the window is 1 %)
  /// m: a surface vertex farther outside the volume makes the volume unusable for this surface (Volume:
  /// an error; Auto: the shell instead, saying why).
  double maxOutside = 0.002;
};

struct SiteDensity {
  PointSampling sampling;
  SiteDensitySource source = SiteDensitySource::Surface;  ///< the one used
  std::string description;  ///< for logs: which source, how many samples, and why when Auto fell back
};

/// The site density of `surface` (which may be open) with an optional volume around it. Throws
/// InvalidInputError naming the problem: bad options, Surface for an open surface, Volume without a volume
/// or with surface vertices farther than maxOutside outside it, or a sampling with no sample.
SiteDensity siteDensity(const mesh::TriangleMesh& surface, const mesh::TetMesh* volume, const SiteDensityOptions& options);

/// `o` for a window of scale h: the grid step `spacing`, or h / 4 when that is 0; a shell thickness <= 0
/// becomes 3 h, where the Hermite window has fallen to exp(-4.5), about 1 %.
SiteDensityOptions forWindow(SiteDensityOptions o, double windowScale, double spacing);

/// "auto", "surface", "volume", "shell"; parseSiteDensitySource throws InvalidInputError for other text.
std::string toString(SiteDensitySource source);
SiteDensitySource parseSiteDensitySource(const std::string& text);

}  // namespace deformation_enrichment::descriptors
