#pragma once
// Blending of example stamps ([Seiler14 eq. 16]) and the displacement mapping of eq. (1),
//   s~(x) = s(x) + e(x),  e(x) = R B Psi(phi, varphi),  (phi, varphi) = (b_x, b_y)^T (x - p),
// with x the rest-state position of a surface vertex, p the contact's rest-state position, B the stamping
// frame in rest axes and R the rotation of the local polar decomposition (rest axes -> deformed axes).
//
// Several contacts (rule, chosen so the surface stays continuous and no vertex gets a stamp twice):
// every contact c has a rim weight a_c(x) = smoothstep((1 - |x - p_c| / R_c) / band) that is 1 inside
// (1 - band) R_c and falls to 0 at the stamp radius R_c (band = 0: a hard cut at R_c). A vertex gets
//   e(x) = sum_c a_c(x) e_c(x) / max(1, sum_c a_c(x)),
// i.e. stamps simply add where their weights sum to at most 1 and are averaged (normalised) only where
// they overlap more than that, so two coinciding contacts give one stamp, not a doubled one. Every term is
// continuous in x and vanishes at the rims, so e is continuous across stamp boundaries. Vertices outside
// every stamp radius are not touched at all (not returned, their state untouched bit for bit). Given rest
// triangles, a stamp reaches only the vertices of its ball connected to the contact through the surface
// (edges with both ends in the ball), so it does not bleed across a narrow cut or through a thin wall; given
// rest normals, a surface stamp leaves back-facing vertices (n . b_z < 0) among those untouched (it would give
// them the value of the side it was rasterised from), while a volume stamp gives them their own.
#include <Eigen/Core>
#include <algorithm>
#include <memory>
#include <opencv2/core.hpp>
#include <vector>

#include "deformation_enrichment/examples/example.hpp"
#include "deformation_enrichment/mesh/vertex_adjacency.hpp"

namespace deformation_enrichment::enrichment {

/// eq. (16): Psi = sum_i w~_i Psi[i] over stamps that share one size (node by node; the stamps are in
/// their examples' frame coordinates, which the canonical frames B and B[i] identify, so T_i acts as the
/// identity on stamp coordinates). Zero weights are skipped. Throws InvalidInputError for no stamps,
/// sizes or types that differ, a weight count that differs, or NaN weights.
cv::Mat blendStamps(const std::vector<cv::Mat>& stamps, const Eigen::VectorXd& weights);

/// eq. (16) over an example set; the examples must share stamp size, layers and radius (returned in `radius`).
cv::Mat blendExampleStamps(const std::vector<examples::Example>& examples, const Eigen::VectorXd& weights, double& radius);

/// One contact's blended stamp placed on the surface.
struct ContactStamp {
  Eigen::Vector3d contact = Eigen::Vector3d::Zero();            ///< p, rest-state position
  Eigen::Matrix3d frame = Eigen::Matrix3d::Identity();          ///< B, rest axes
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();       ///< R, rest axes -> deformed axes
  cv::Mat stamp;                                                ///< Psi, CV_32FC3 (stamp.hpp)
  double radius = 0.0;
  int layers = 1;                                               ///< 1: surface stamp, >= 2: volume stamp
};

/// The enrichment e restricted to the vertices it touches.
struct SurfaceEnrichment {
  std::vector<int> vertices;       ///< ascending vertex ids
  Eigen::Matrix3Xd displacements;  ///< e at those vertices (world / deformed axes)
};

/// Displacement mapping onto one rest surface; the KD-tree (nanoflann) is built once here.
class StampMapper {
public:
  /// `restVertices`: rest-state surface positions. rimBand in [0, 1). `restNormals` (optional, 3 x n or
  /// empty): vertices whose rest normal points away from the contact's b_z (n . b_z < 0, the far side
  /// of a thin part inside the ball) are skipped. `restTriangles` (optional, 3 x T or empty): a stamp
  /// reaches only the part of its ball connected through triangle edges, both ends in the ball, to the ball
  /// vertex nearest the contact (empty: the whole ball, e.g. for a point cloud). Throws InvalidInputError
  /// for no vertices, NaN, a band outside [0, 1), normals of the wrong size or triangle indices out of range.
  explicit StampMapper(Eigen::Matrix3Xd restVertices, double rimBand = 0.2, Eigen::Matrix3Xd restNormals = Eigen::Matrix3Xd(),
                       const Eigen::Matrix3Xi& restTriangles = Eigen::Matrix3Xi());
  ~StampMapper();
  StampMapper(StampMapper&&) noexcept;
  StampMapper& operator=(StampMapper&&) noexcept;

  Eigen::Index size() const { return rest_.cols(); }
  double rimBand() const { return rimBand_; }
  const Eigen::Matrix3Xd& restVertices() const { return rest_; }

  /// Rim weight a(r) for r = distance / radius (1 inside 1 - band, smoothstep to 0 at r = 1).
  double rimWeight(double relativeDistance) const {
    if (relativeDistance > 1.0) return 0.0;
    if (rimBand_ == 0.0) return 1.0;
    const double s = std::clamp((1.0 - relativeDistance) / rimBand_, 0.0, 1.0);
    return s * s * (3.0 - 2.0 * s);  // smoothstep: C1 at both ends of the band
  }

  /// e for the given contacts (may be empty: nothing touched). Reuses internal scratch, so one mapper
  /// must not be used from two threads at once. Throws InvalidInputError for an invalid contact (NaN,
  /// non-orthonormal frame or rotation, bad stamp or radius).
  void map(const std::vector<ContactStamp>& contacts, SurfaceEnrichment& out);

  /// s~ = s + e (eq. 1) in place on the coarse state (3 x size()); untouched vertices keep their bits.
  void apply(const SurfaceEnrichment& enrichment, Eigen::Matrix3Xd& state) const;

private:
  struct KdTree;
  Eigen::Matrix3Xd rest_;
  double rimBand_;
  Eigen::Matrix3Xd normals_;  // empty: no facing test
  mesh::VertexAdjacency adjacency_;  // no vertices: no surface filter (the whole ball)
  std::unique_ptr<KdTree> index_;
  // Scratch of map(): slot_ (one per vertex, -1 between calls) indexes the compact entries of the touched
  // vertices, sums_ (sum_c a_c e_c) and weights_ (sum_c a_c), in the order they were reached; a few
  // hundred kilobytes of slots stay in the cache where per-vertex sums would not.
  std::vector<int> slot_;
  std::vector<int> touched_;
  std::vector<Eigen::Vector3d> sums_;
  std::vector<double> weights_;
};

}  // namespace deformation_enrichment::enrichment
