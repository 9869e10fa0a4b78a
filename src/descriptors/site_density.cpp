#include "deformation_enrichment/descriptors/site_density.hpp"

#include <cmath>

#include "deformation_enrichment/descriptors/interior_sampling.hpp"
#include "deformation_enrichment/descriptors/shell_sampling.hpp"
#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/barycentric_embedding.hpp"
#include "deformation_enrichment/mesh/surface_report.hpp"
#include "deformation_enrichment/mesh/tet_surface.hpp"

namespace deformation_enrichment::descriptors {
namespace {

std::string millimetres(double metres) {
  const double mm = std::round(metres * 1e4) / 10.0;
  std::string text = std::to_string(mm);
  text.erase(text.find_last_not_of('0') + 1);
  if (text.back() == '.') text.pop_back();
  return text + " mm";
}

SiteDensity interior(const mesh::TriangleMesh& surface, const SiteDensityOptions& o) {
  PointSampling sampling = sampleClosedSurfaceInterior(surface, o.spacing);
  const std::string text = "interior of the closed surface: " + std::to_string(sampling.size()) + " samples";
  return {std::move(sampling), SiteDensitySource::Surface, text};
}

// Throws (embedPoints' message: how many vertices, how far) when the volume does not hold the surface.
SiteDensity insideVolume(const mesh::TriangleMesh& surface, const mesh::TetMesh& volume, const SiteDensityOptions& o) {
  const mesh::EmbeddingReport held = mesh::embedPoints(volume, surface.vertices, o.maxOutside).report;
  PointSampling sampling = sampleClosedSurfaceInterior(mesh::extractSurface(volume).surface, o.spacing);
  const std::string text = "volume (" + std::to_string(volume.numTets()) + " tets): " + std::to_string(sampling.size()) +
                           " samples; " + mesh::describe(held, surface.numVertices());
  return {std::move(sampling), SiteDensitySource::Volume, text};
}

SiteDensity shell(const mesh::TriangleMesh& surface, const SiteDensityOptions& o, const std::string& why) {
  PointSampling sampling = sampleShellUnderSurface(surface, o.shellThickness, o.spacing);
  const std::string text = "shell " + millimetres(o.shellThickness) + " under the surface" + why + ": " +
                           std::to_string(sampling.size()) + " samples";
  return {std::move(sampling), SiteDensitySource::Shell, text};
}

}  // namespace

SiteDensity siteDensity(const mesh::TriangleMesh& surface, const mesh::TetMesh* volume, const SiteDensityOptions& o) {
  if (!(o.spacing > 0.0) || !std::isfinite(o.spacing)) throw InvalidInputError("site density: spacing must be positive and finite");
  if (!(o.shellThickness > 0.0) || !std::isfinite(o.shellThickness))
    throw InvalidInputError("site density: shell thickness must be positive and finite");
  if (!(o.maxOutside >= 0.0)) throw InvalidInputError("site density: max_outside must be >= 0");
  const mesh::SurfaceReport report = mesh::inspectSurface(surface);
  const bool closed = report.boundaryEdges == 0;
  switch (o.source) {
    case SiteDensitySource::Surface:
      if (!closed)
        throw InvalidInputError("site density: the surface is open (" + std::to_string(report.boundaryEdges) +
                                " boundary edges), so it has no interior; use a volume or a shell");
      return interior(surface, o);
    case SiteDensitySource::Volume:
      if (volume == nullptr) throw InvalidInputError("site density: no volume given");
      return insideVolume(surface, *volume, o);
    case SiteDensitySource::Shell:
      return shell(surface, o, "");
    case SiteDensitySource::Auto:
      break;
  }
  if (closed) return interior(surface, o);
  if (volume == nullptr) return shell(surface, o, " (open surface, no volume)");
  try {
    return insideVolume(surface, *volume, o);
  } catch (const InvalidInputError& e) {
    return shell(surface, o, std::string(" (the volume was refused: ") + e.what() + ")");
  }
}

SiteDensityOptions forWindow(SiteDensityOptions o, double windowScale, double spacing) {
  o.spacing = spacing > 0.0 ? spacing : windowScale / 4.0;
  if (!(o.shellThickness > 0.0)) o.shellThickness = 3.0 * windowScale;
  return o;
}

std::string toString(SiteDensitySource source) {
  switch (source) {
    case SiteDensitySource::Auto: return "auto";
    case SiteDensitySource::Surface: return "surface";
    case SiteDensitySource::Volume: return "volume";
    case SiteDensitySource::Shell: return "shell";
  }
  return "auto";
}

SiteDensitySource parseSiteDensitySource(const std::string& text) {
  for (SiteDensitySource s : {SiteDensitySource::Auto, SiteDensitySource::Surface, SiteDensitySource::Volume, SiteDensitySource::Shell})
    if (text == toString(s)) return s;
  throw InvalidInputError("site density: '" + text + "' is not one of auto, surface, volume, shell");
}

}  // namespace deformation_enrichment::descriptors
