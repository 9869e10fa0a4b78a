#include "deformation_enrichment/enrichment/tool_tip.hpp"

#include <urdf_parser/urdf_parser.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/closest_point_on_triangle.hpp"

namespace deformation_enrichment::enrichment {
using mesh::closestPointOnTriangle;

namespace {

// Exact signed distance functions of the three URDF primitives, centred at their own origin.
double sphereDistance(const Eigen::Vector3d& p, double radius) { return p.norm() - radius; }

double boxDistance(const Eigen::Vector3d& p, const Eigen::Vector3d& extents) {
  const Eigen::Vector3d q = p.cwiseAbs() - extents / 2.0;
  return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
}

double cylinderDistance(const Eigen::Vector3d& p, double radius, double length) {  // axis z, as in URDF
  const Eigen::Vector2d d(p.head<2>().norm() - radius, std::abs(p.z()) - length / 2.0);
  return d.cwiseMax(0.0).norm() + std::min(d.maxCoeff(), 0.0);
}

// Alternating projections stop when the distance is bracketed this tightly [m] or after this many steps.
constexpr double kDistanceTolerance = 1e-7;
constexpr int kMaxProjections = 500;

// The point of the solid primitive nearest to p (p itself when inside), in the primitive's frame.
Eigen::Vector3d projectOnto(const TipPrimitive& tip, const Eigen::Vector3d& p) {
  switch (tip.shape) {
    case TipPrimitive::Shape::Sphere: {
      const double n = p.norm();
      return n <= tip.size.x() ? p : Eigen::Vector3d(p * (tip.size.x() / n));
    }
    case TipPrimitive::Shape::Cylinder: {
      Eigen::Vector3d q = p;
      const double radial = p.head<2>().norm();
      if (radial > tip.size.x()) q.head<2>() *= tip.size.x() / radial;
      q.z() = std::clamp(p.z(), -tip.size.y() / 2.0, tip.size.y() / 2.0);
      return q;
    }
    case TipPrimitive::Shape::Box: return p.cwiseMax(-tip.size / 2.0).cwiseMin(tip.size / 2.0);
  }
  return p;
}

double primitiveDistance(const TipPrimitive& tip, const Eigen::Vector3d& p) {
  switch (tip.shape) {
    case TipPrimitive::Shape::Sphere: return sphereDistance(p, tip.size.x());
    case TipPrimitive::Shape::Cylinder: return cylinderDistance(p, tip.size.x(), tip.size.y());
    case TipPrimitive::Shape::Box: return boxDistance(p, tip.size);
  }
  return p.norm();
}

Eigen::Isometry3d isometry(const urdf::Pose& pose) {
  Eigen::Isometry3d result = Eigen::Isometry3d::Identity();
  result.translation() = Eigen::Vector3d(pose.position.x, pose.position.y, pose.position.z);
  result.linear() = Eigen::Quaterniond(pose.rotation.w, pose.rotation.x, pose.rotation.y, pose.rotation.z).normalized()
                        .toRotationMatrix();
  return result;
}

TipPrimitive primitive(const urdf::Collision& collision, const std::string& link) {
  if (!collision.geometry) throw InvalidInputError("URDF link '" + link + "' has a collision element without geometry");
  TipPrimitive result;
  result.origin = isometry(collision.origin);
  switch (collision.geometry->type) {
    case urdf::Geometry::SPHERE:
      result.shape = TipPrimitive::Shape::Sphere;
      result.size.x() = static_cast<const urdf::Sphere&>(*collision.geometry).radius;
      break;
    case urdf::Geometry::CYLINDER: {
      const auto& cylinder = static_cast<const urdf::Cylinder&>(*collision.geometry);
      result.shape = TipPrimitive::Shape::Cylinder;
      result.size = Eigen::Vector3d(cylinder.radius, cylinder.length, 1.0);
      break;
    }
    case urdf::Geometry::BOX: {
      const auto& box = static_cast<const urdf::Box&>(*collision.geometry);
      result.shape = TipPrimitive::Shape::Box;
      result.size = Eigen::Vector3d(box.dim.x, box.dim.y, box.dim.z);
      break;
    }
    default:
      throw InvalidInputError("URDF link '" + link +
                              "': mesh collision geometry is not supported for the tool tip (use a sphere, cylinder or box)");
  }
  const int used = result.shape == TipPrimitive::Shape::Sphere ? 1 : result.shape == TipPrimitive::Shape::Cylinder ? 2 : 3;
  if (!result.size.head(used).allFinite() || result.size.head(used).minCoeff() <= 0.0 || !result.origin.matrix().allFinite())
    throw InvalidInputError("URDF link '" + link + "': collision geometry with non-positive or non-finite dimensions");
  return result;
}

}  // namespace

ToolTip::ToolTip(std::string link, std::vector<TipPrimitive> primitives)
    : link_(std::move(link)), primitives_(std::move(primitives)) {
  for (const TipPrimitive& tip : primitives_) toPrimitive_.push_back(tip.origin.inverse());
  // Bounding ball: around the mean of the primitives' centres, each primitive's own ball inside it.
  if (primitives_.empty()) return;
  for (const TipPrimitive& tip : primitives_) boundCentre_ += tip.origin.translation() / static_cast<double>(primitives_.size());
  for (const TipPrimitive& tip : primitives_) {
    const double own = tip.shape == TipPrimitive::Shape::Sphere     ? tip.size.x()
                       : tip.shape == TipPrimitive::Shape::Cylinder ? std::hypot(tip.size.x(), tip.size.y() / 2.0)
                                                                     : tip.size.norm() / 2.0;
    boundRadius_ = std::max(boundRadius_, (tip.origin.translation() - boundCentre_).norm() + own);
  }
}

double ToolTip::signedDistance(const Eigen::Vector3d& pointInLink) const {
  if (primitives_.empty()) return pointInLink.norm();
  double distance = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < primitives_.size(); ++i)
    distance = std::min(distance, primitiveDistance(primitives_[i], toPrimitive_[i] * pointInLink));
  return distance;
}

double ToolTip::triangleDistance(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                                 Eigen::Vector3d* closest) const {
  if (primitives_.empty()) {  // a point tip at the link origin
    const Eigen::Vector3d x = closestPointOnTriangle(Eigen::Vector3d::Zero(), a, b, c);
    if (closest) *closest = x;
    return x.norm();
  }
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < primitives_.size(); ++i) {
    const TipPrimitive& tip = primitives_[i];
    const Eigen::Vector3d pa = toPrimitive_[i] * a, pb = toPrimitive_[i] * b, pc = toPrimitive_[i] * c;
    // Cheney-Goldstein alternating projections: triangle point x -> nearest tip point y -> nearest triangle
    // point. |x - y| bounds the distance from above; the plane through y normal to x - y supports the tip,
    // so the triangle's lowest vertex over that plane bounds it from below: stop when the bounds meet.
    Eigen::Vector3d x = closestPointOnTriangle(Eigen::Vector3d::Zero(), pa, pb, pc);
    double distance = primitiveDistance(tip, x);
    for (int iteration = 0; iteration < kMaxProjections && distance > kDistanceTolerance; ++iteration) {
      const Eigen::Vector3d y = projectOnto(tip, x);
      const Eigen::Vector3d n = (x - y).normalized();
      const double lower = std::min({n.dot(pa - y), n.dot(pb - y), n.dot(pc - y)});
      if (distance - lower <= kDistanceTolerance) break;
      const Eigen::Vector3d next = closestPointOnTriangle(y, pa, pb, pc);
      const double nextDistance = primitiveDistance(tip, next);
      if (!(nextDistance < distance)) break;  // no progress left (distances decrease monotonically)
      x = next;
      distance = nextDistance;
    }
    if (distance < best) {
      best = distance;
      if (closest) *closest = toPrimitive_[i].inverse() * x;
    }
  }
  return best;
}

std::string ToolTip::description() const {
  if (primitives_.empty()) return "point (tool pose position)";
  std::ostringstream out;
  for (std::size_t i = 0; i < primitives_.size(); ++i) {
    const TipPrimitive& tip = primitives_[i];
    if (i > 0) out << " + ";
    switch (tip.shape) {
      case TipPrimitive::Shape::Sphere: out << "sphere r=" << tip.size.x() << " m"; break;
      case TipPrimitive::Shape::Cylinder: out << "cylinder r=" << tip.size.x() << " m l=" << tip.size.y() << " m"; break;
      case TipPrimitive::Shape::Box:
        out << "box " << tip.size.x() << " x " << tip.size.y() << " x " << tip.size.z() << " m";
        break;
    }
  }
  out << " of link '" << link_ << "'";
  return out.str();
}

ToolTip toolTipFromUrdf(const std::string& urdfXml, const std::string& link) {
  if (urdfXml.empty()) throw InvalidInputError("robot_description is empty");
  const urdf::ModelInterfaceSharedPtr model = urdf::parseURDF(urdfXml);
  if (!model) throw InvalidInputError("robot_description is not a valid URDF (urdfdom could not parse it)");
  const urdf::LinkConstSharedPtr tipLink = model->getLink(link);
  if (!tipLink) throw InvalidInputError("URDF '" + model->getName() + "' has no link '" + link + "'");
  std::vector<TipPrimitive> primitives;
  for (const auto& collision : tipLink->collision_array)
    if (collision) primitives.push_back(primitive(*collision, link));
  if (primitives.empty() && tipLink->collision) primitives.push_back(primitive(*tipLink->collision, link));
  if (primitives.empty()) throw InvalidInputError("URDF link '" + link + "' has no collision geometry");
  return ToolTip(link, std::move(primitives));
}

}  // namespace deformation_enrichment::enrichment
