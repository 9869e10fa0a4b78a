#pragma once
// The tool tip's collision geometry, read from the URDF in robot_description, for deriving contacts from a
// tool pose: the tool touches the surface where the tip's surface comes within the contact distance of it.
// Without a URDF the tip is a point (the pose's position), the behaviour before URDF support.
#include <Eigen/Geometry>
#include <string>
#include <vector>

namespace deformation_enrichment::enrichment {

struct TipPrimitive {
  enum class Shape { Sphere, Cylinder, Box };
  Shape shape = Shape::Sphere;
  Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();  ///< collision frame in the tip link's frame
  Eigen::Vector3d size = Eigen::Vector3d::Zero();  ///< sphere (r, -, -), cylinder (r, length, -) along z, box extents
};

class ToolTip {
public:
  /// A point tip at the link origin.
  ToolTip() = default;
  explicit ToolTip(std::string link, std::vector<TipPrimitive> primitives);

  bool isPoint() const { return primitives_.empty(); }
  const std::string& link() const { return link_; }
  const std::vector<TipPrimitive>& primitives() const { return primitives_; }

  /// Signed distance of a point (in the tip link's frame) to the tip surface, negative inside; the union
  /// of the collision primitives (smallest distance). A point tip: distance to the link origin.
  double signedDistance(const Eigen::Vector3d& pointInLink) const;

  /// Distance from the tip to the triangle (a, b, c) (link frame): the smallest signed distance of a
  /// triangle point, found per primitive by alternating projections between the two convex sets (they
  /// converge to a closest pair for disjoint sets; every iterate is a triangle point, so the result never
  /// under-estimates the distance; stopped when a supporting-plane lower bound is within 0.1 um). When the
  /// triangle cuts into the tip the result is <= 0 or a few um above (the iterates approach the
  /// intersection from outside), not the depth. `closest` receives the triangle point attaining it.
  double triangleDistance(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                          Eigen::Vector3d* closest = nullptr) const;

  /// A ball (link frame) containing the tip: signedDistance(p) >= |p - centre| - radius, a cheap lower bound.
  const Eigen::Vector3d& boundCentre() const { return boundCentre_; }
  double boundRadius() const { return boundRadius_; }

  /// e.g. "sphere r=0.004 m of link 'tool_tip'" (for logs and diagnostics).
  std::string description() const;

private:
  std::string link_;
  std::vector<TipPrimitive> primitives_;
  std::vector<Eigen::Isometry3d> toPrimitive_;  // inverse origins, per primitive
  Eigen::Vector3d boundCentre_ = Eigen::Vector3d::Zero();
  double boundRadius_ = 0.0;
};

/// The collision geometry of `link` in the URDF text `urdfXml`. Throws InvalidInputError naming the
/// problem: unparsable URDF, no such link, no collision element, mesh geometry (unsupported), or
/// non-positive / non-finite dimensions.
ToolTip toolTipFromUrdf(const std::string& urdfXml, const std::string& link);

}  // namespace deformation_enrichment::enrichment
