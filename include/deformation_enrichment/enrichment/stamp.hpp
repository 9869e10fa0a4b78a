#pragma once
// Stamps Psi: R^2 -> R^3 of [Seiler14 §3], stored as a regular grid of nodes (OpenCV CV_32FC3) spanning
// [-R, R]^2 in a stamping frame B around a contact p: node (row j, col k) sits at
//   (phi, varphi) = (-R + k 2R/(cols-1), -R + j 2R/(rows-1)),  phi along b_x, varphi along b_y,
// so the grid covers the square exactly and bilinear look-up reproduces affine fields everywhere in it.
// Values are displacements (fine - coarse) in frame coordinates (components along b_x, b_y, b_z).
#include <Eigen/Core>
#include <algorithm>
#include <opencv2/core.hpp>

#include "deformation_enrichment/mesh/triangle_mesh.hpp"

namespace deformation_enrichment::enrichment {

/// Stamp coordinates (phi, varphi) of points: the projection of x - p on (b_x, b_y) (eq. 1's mapping).
Eigen::Matrix2Xd stampCoordinates(const Eigen::Matrix3Xd& points, const Eigen::Vector3d& p, const Eigen::Matrix3d& B);

/// Rasterises a stamp from a surface patch: the patch's rest vertices are projected on (b_x, b_y) around
/// p and each node takes the linear (barycentric) interpolation of `frameDisplacement` (3 x vertices,
/// already in frame coordinates) over the projected triangle that contains it. Where projected triangles
/// overlap (a folded or two-sided patch) the one highest along b_z wins, i.e. the side seen from outside.
/// Nodes no triangle covers get zero. Throws InvalidInputError for an invalid mesh, mismatched sizes,
/// NaN, a non-orthonormal B, radius <= 0 or resolution < 2.
cv::Mat rasteriseStamp(const mesh::TriangleMesh& restPatch, const Eigen::Matrix3Xd& frameDisplacement,
                       const Eigen::Vector3d& p, const Eigen::Matrix3d& B, double radius, int resolution = 64);

/// Rasterises the stamp of a displacement field on a whole surface: the patch of triangles that face b_z
/// (seen from outside) and lie within reach of the stamp square around p (sqrt(2) R plus two `edge`
/// lengths, `edge` the surface's longest edge) is cut out, `displacement` (3 x surface vertices, world
/// axes) is brought to frame coordinates by `toFrame` and rasterised with rasteriseStamp. Throws
/// InvalidInputError when no triangle faces the contact near p.
cv::Mat rasteriseFacingPatch(const mesh::TriangleMesh& surface, const Eigen::Matrix3Xd& displacement, const Eigen::Vector3d& p,
                             const Eigen::Matrix3d& toFrame, const Eigen::Matrix3d& B, double radius, int resolution,
                             double edge);

/// Bilinear look-up of `stamp` (CV_32FC3 over [-radius, radius]^2) at stamp coordinates (2 x n), in
/// double precision; zero outside the square. `out` is resized to 3 x n. Throws InvalidInputError for a
/// wrong stamp type or size, radius <= 0, or NaN coordinates.
void lookUpStamp(const cv::Mat& stamp, double radius, const Eigen::Matrix2Xd& coordinates, Eigen::Matrix3Xd& out);

/// Single-point look-up (same conventions as lookUpStamp, no input checks: the caller validated). Inline:
/// the mapping calls it for every vertex of a stamp.
inline Eigen::Vector3d sampleStamp(const cv::Mat& stamp, double radius, double phi, double varphi) {
  // Continuous node coordinates; the square [-R, R]^2 maps onto [0, cols-1] x [0, rows-1].
  const double nodesPerMetre = 0.5 / radius;  // one division, shared by both axes
  double x = (phi + radius) * ((stamp.cols - 1) * nodesPerMetre);
  double y = (varphi + radius) * ((stamp.rows - 1) * nodesPerMetre);
  // A point on the far edge (phi = R) can land a few ulps past the last node: it is on the edge, not out.
  if (x > stamp.cols - 1 && x <= (stamp.cols - 1) * (1.0 + 1e-12)) x = stamp.cols - 1;
  if (y > stamp.rows - 1 && y <= (stamp.rows - 1) * (1.0 + 1e-12)) y = stamp.rows - 1;
  if (!(x >= 0.0 && y >= 0.0 && x <= stamp.cols - 1 && y <= stamp.rows - 1)) return Eigen::Vector3d::Zero();
  const int k = std::min(static_cast<int>(x), stamp.cols - 2);
  const int j = std::min(static_cast<int>(y), stamp.rows - 2);
  const double fx = x - k, fy = y - j;
  const cv::Vec3f* row0 = stamp.ptr<cv::Vec3f>(j);
  const cv::Vec3f* row1 = stamp.ptr<cv::Vec3f>(j + 1);
  Eigen::Vector3d out;
  for (int c = 0; c < 3; ++c) {
    const double top = (1.0 - fx) * row0[k][c] + fx * row0[k + 1][c];
    const double bottom = (1.0 - fx) * row1[k][c] + fx * row1[k + 1][c];
    out[c] = (1.0 - fy) * top + fy * bottom;
  }
  return out;
}

/// Throws InvalidInputError unless `stamp` is a CV_32FC3 grid of at least 2x2 nodes and radius > 0.
void checkStamp(const cv::Mat& stamp, double radius, const char* what);

}  // namespace deformation_enrichment::enrichment
