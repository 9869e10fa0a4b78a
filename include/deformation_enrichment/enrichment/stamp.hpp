#pragma once
// Stamps Psi of [Seiler14 §3], stored as regular grids of nodes (OpenCV CV_32FC3) in a stamping frame B
// around a contact p. Values are displacements (fine - coarse) in frame coordinates (components along b_x,
// b_y, b_z).
//   - Surface stamp (the paper's, one layer): Psi: R^2 -> R^3 over [-R, R]^2; node (row j, col k) sits at
//       (phi, varphi) = (-R + k 2R/(cols-1), -R + j 2R/(rows-1)),  phi along b_x, varphi along b_y,
//     so the grid covers the square exactly and bilinear look-up reproduces affine fields everywhere in it.
//     A vertex takes the value at its projection on (b_x, b_y), whatever its height along b_z.
//   - Volume stamp (L >= 2 layers): Psi: R^3 -> R^3 over the cube [-R, R]^3, the fine - coarse displacement
//     of the volume around the contact; layer l (rows l n .. (l+1) n - 1 of an (L n) x n grid) sits at height
//     zeta = b_z . (x - p) = -R + l 2R/(L-1). A vertex takes the trilinear value at (phi, varphi, zeta), so
//     the sides of a thin part and the far side of a bend get their own detail instead of the value of
//     the surface above them, which the surface stamp gives them (on the slab's edges: 40-60 % of the
//     held-out error of an example's own stamp; docs/accuracy.md).
#include <Eigen/Core>
#include <algorithm>
#include <opencv2/core.hpp>
#include <vector>

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

/// World positions of a volume stamp's nodes around p in frame B, node (l, j, k) at column (l n + j) n + k.
Eigen::Matrix3Xd volumeStampNodes(const Eigen::Vector3d& p, const Eigen::Matrix3d& B, double radius, int resolution, int layers);

/// A volume stamp from values at its nodes (3 x nodes, frame coordinates, the order of volumeStampNodes).
/// Nodes not `known` (outside the object, where the field is not defined) take the value of the nearest
/// known node in grid steps (ties: the mean of the known nodes reached in the same step), so trilinear
/// look-up just inside the surface is not pulled towards zero. Throws InvalidInputError for sizes that do
/// not match, no known node, or non-finite known values.
cv::Mat volumeStampFromNodes(const Eigen::Matrix3Xd& values, const std::vector<char>& known, int resolution, int layers);

/// Bilinear look-up of `stamp` (CV_32FC3 over [-radius, radius]^2) at stamp coordinates (2 x n), in
/// double precision; zero outside the square. `out` is resized to 3 x n. Throws InvalidInputError for a
/// wrong stamp type or size, radius <= 0, or NaN coordinates.
void lookUpStamp(const cv::Mat& stamp, double radius, const Eigen::Matrix2Xd& coordinates, Eigen::Matrix3Xd& out);

namespace detail {
/// Bilinear look-up in the `rows` x cols block of `stamp` that starts at row `firstRow`; zero outside.
inline Eigen::Vector3d sampleBlock(const cv::Mat& stamp, int firstRow, int rows, double radius, double phi, double varphi) {
  // Continuous node coordinates; the square [-R, R]^2 maps onto [0, cols-1] x [0, rows-1].
  const double nodesPerMetre = 0.5 / radius;  // one division, shared by both axes
  double x = (phi + radius) * ((stamp.cols - 1) * nodesPerMetre);
  double y = (varphi + radius) * ((rows - 1) * nodesPerMetre);
  // A point on the far edge (phi = R) can land a few ulps past the last node: it is on the edge, not out.
  if (x > stamp.cols - 1 && x <= (stamp.cols - 1) * (1.0 + 1e-12)) x = stamp.cols - 1;
  if (y > rows - 1 && y <= (rows - 1) * (1.0 + 1e-12)) y = rows - 1;
  if (!(x >= 0.0 && y >= 0.0 && x <= stamp.cols - 1 && y <= rows - 1)) return Eigen::Vector3d::Zero();
  const int k = std::min(static_cast<int>(x), stamp.cols - 2);
  const int j = std::min(static_cast<int>(y), rows - 2);
  const double fx = x - k, fy = y - j;
  const cv::Vec3f* row0 = stamp.ptr<cv::Vec3f>(firstRow + j);
  const cv::Vec3f* row1 = stamp.ptr<cv::Vec3f>(firstRow + j + 1);
  Eigen::Vector3d out;
  for (int c = 0; c < 3; ++c) {
    const double top = (1.0 - fx) * row0[k][c] + fx * row0[k + 1][c];
    const double bottom = (1.0 - fx) * row1[k][c] + fx * row1[k + 1][c];
    out[c] = (1.0 - fy) * top + fy * bottom;
  }
  return out;
}
}  // namespace detail

/// Single-point look-up (same conventions as lookUpStamp, no input checks: the caller validated). Inline:
/// the mapping calls it for every vertex of a stamp.
inline Eigen::Vector3d sampleStamp(const cv::Mat& stamp, double radius, double phi, double varphi) {
  return detail::sampleBlock(stamp, 0, stamp.rows, radius, phi, varphi);
}

/// Trilinear look-up of a volume stamp of `layers` (>= 2) square layers at (phi, varphi, zeta); zero outside
/// the cube. No input checks (the caller validated).
inline Eigen::Vector3d sampleVolumeStamp(const cv::Mat& stamp, double radius, int layers, double phi, double varphi, double zeta) {
  const int n = stamp.cols;
  double z = (zeta + radius) * ((layers - 1) * 0.5 / radius);
  if (z > layers - 1 && z <= (layers - 1) * (1.0 + 1e-12)) z = layers - 1;
  if (!(z >= 0.0 && z <= layers - 1)) return Eigen::Vector3d::Zero();
  const int l = std::min(static_cast<int>(z), layers - 2);
  const double fz = z - l;
  return (1.0 - fz) * detail::sampleBlock(stamp, l * n, n, radius, phi, varphi) +
         fz * detail::sampleBlock(stamp, (l + 1) * n, n, radius, phi, varphi);
}

/// Throws InvalidInputError unless `stamp` is a CV_32FC3 grid of at least 2x2 nodes (per layer: `layers`
/// square layers stacked along rows when layers >= 2) and radius > 0.
void checkStamp(const cv::Mat& stamp, double radius, int layers, const char* what);

}  // namespace deformation_enrichment::enrichment
