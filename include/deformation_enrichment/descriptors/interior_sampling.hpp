#pragma once
// Volume samples of a closed triangle surface, for site descriptors of objects given only by their surface
// (OBJ/PLY): the cell centres of a regular grid that lie inside, each carrying the cell volume s^3.
// Inside is decided by ray parity along +z per grid column: every triangle is intersected once with the
// columns under its xy-projection, so the cost is O(triangles x columns per triangle + samples).
#include "deformation_enrichment/descriptors/point_sampling.hpp"
#include "deformation_enrichment/mesh/triangle_mesh.hpp"

namespace deformation_enrichment::descriptors {

/// Cell centres of the SampleGrid over the surface's bounding box (step <= spacing, metres) that lie
/// inside. The volume quadrature of these samples is the midpoint rule: error O(spacing^2) away from the
/// surface, O(spacing) from the boundary cells.
/// Throws InvalidInputError for an invalid surface, a non-positive spacing, more than `maxSamples` grid
/// cells, a column crossed an odd number of times (surface not closed) or no inside sample.
PointSampling sampleClosedSurfaceInterior(const mesh::TriangleMesh& surface, double spacing,
                                          long maxSamples = 50'000'000);

}  // namespace deformation_enrichment::descriptors
