#pragma once
// A smooth closed display surface from a label image, by VTK [VTK]: the object's voxels (labels >=
// minLabel) as a 0/1 field, Gaussian-smoothed (removes the voxel staircase, anisotropic voxels alike),
// contoured (at 1/2 by default) by marching cubes [Lorensen87], the largest connected piece kept, decimated to a
// vertex budget by quadric error [Garland97], smoothed by a windowed-sinc filter [Taubin96]. VTK's serial
// filters only, so the result does not depend on thread counts.
#include "deformation_enrichment/mesh/label_image.hpp"
#include "deformation_enrichment/mesh/triangle_mesh.hpp"

namespace deformation_enrichment::mesh {

struct ImageSurfaceOptions {
  int minLabel = 1;                 ///< voxels with a label >= this are the object
  double smoothingSigma = 1.5e-3;   ///< Gaussian standard deviation in metres (0: none)
  int targetVertices = 10000;       ///< vertex budget of the decimated surface (approximate)
  int smoothingIterations = 20;     ///< windowed-sinc iterations (0: none)
  /// Level of the smoothed 0/1 field to contour, in (0, 1): 1/2 follows the object's boundary, less
  /// grows the surface outwards (a coarse volume that encloses the display surface).
  double isoValue = 0.5;
};

/// The object's boundary in metres (image origin at voxel (0, 0, 0)), outward-oriented, closed and
/// manifold. Throws InvalidInputError if no voxel has a label >= minLabel or for invalid options, and
/// NumericalError if the filters do not give a closed manifold surface.
TriangleMesh imageSurface(const LabelImage& image, const ImageSurfaceOptions& options = {});

}  // namespace deformation_enrichment::mesh
