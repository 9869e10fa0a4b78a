#pragma once
// Volume samples of a shell under an open surface, for the site density ([Seiler14 eq. 7]) of a surface
// that encloses nothing and comes with no volume (a skin patch, the visible part of an organ): the material
// is taken to be everything within `thickness` behind the surface. The grid is the one of
// sampleClosedSurfaceInterior (cells tiling the box, centres shifted by irrational fractions of a cell), so a
// shell as thick as a closed object's interior gives the same samples there.
#include "deformation_enrichment/descriptors/point_sampling.hpp"
#include "deformation_enrichment/mesh/triangle_mesh.hpp"

namespace deformation_enrichment::descriptors {

/// Cell centres of the surface's SampleGrid, grown by whole cells to reach `thickness` beyond its box, that
/// lie within `thickness` of the surface and behind it: x - p points into the surface (within 60 degrees
/// of -n at creases), for p the nearest surface point and n the interpolated vertex normal there (outward,
/// counter-clockwise triangles), and p is not on the open rim (cells beside the rim are not material).
/// Each carries the cell volume. Throws
/// InvalidInputError for an invalid surface, a non-positive spacing or thickness, more than `maxSamples`
/// grid cells, or no sample.
PointSampling sampleShellUnderSurface(const mesh::TriangleMesh& surface, double thickness, double spacing,
                                      long maxSamples = 50'000'000);

}  // namespace deformation_enrichment::descriptors
