#include "deformation_enrichment/mesh/label_image.hpp"

#include <CGAL/Image_3.h>

#include <cstring>
#include <fstream>

#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::mesh {

LabelImage readLabelImage(const std::string& path) {
  if (!std::ifstream(path).good()) throw IoError("cannot open image " + path);
  CGAL::Image_3 image;
  if (!image.read(path)) throw IoError("image " + path + " could not be read by CGAL ImageIO");
  const _image* raw = image.image();
  if (raw->wdim != 1 || raw->wordKind != WK_FIXED || raw->sign != SGN_UNSIGNED || raw->vdim != 1)
    throw IoError("image " + path + " is not an 8-bit unsigned label image");
  LabelImage labels;
  labels.size << int(image.xdim()), int(image.ydim()), int(image.zdim());
  labels.spacing << image.vx(), image.vy(), image.vz();
  labels.spacing *= 1e-3;
  if (!(labels.spacing.minCoeff() > 0.0) || labels.size.minCoeff() <= 0)
    throw IoError("image " + path + " has an empty size or a non-positive voxel size");
  labels.labels.resize(image.size());
  std::memcpy(labels.labels.data(), image.data(), image.size());
  return labels;
}

}  // namespace deformation_enrichment::mesh
