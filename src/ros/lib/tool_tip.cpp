#include "deformation_enrichment/ros/tool_tip.hpp"

#include <urdf/model.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::ros_layer {
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
}

double ToolTip::signedDistance(const Eigen::Vector3d& pointInLink) const {
  if (primitives_.empty()) return pointInLink.norm();
  double distance = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < primitives_.size(); ++i) {
    const TipPrimitive& tip = primitives_[i];
    const Eigen::Vector3d p = toPrimitive_[i] * pointInLink;
    switch (tip.shape) {
      case TipPrimitive::Shape::Sphere: distance = std::min(distance, sphereDistance(p, tip.size.x())); break;
      case TipPrimitive::Shape::Cylinder: distance = std::min(distance, cylinderDistance(p, tip.size.x(), tip.size.y())); break;
      case TipPrimitive::Shape::Box: distance = std::min(distance, boxDistance(p, tip.size)); break;
    }
  }
  return distance;
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
  urdf::Model model;
  if (!model.initString(urdfXml)) throw InvalidInputError("robot_description is not a valid URDF (urdfdom could not parse it)");
  const urdf::LinkConstSharedPtr tipLink = model.getLink(link);
  if (!tipLink) throw InvalidInputError("URDF '" + model.getName() + "' has no link '" + link + "'");
  std::vector<TipPrimitive> primitives;
  for (const auto& collision : tipLink->collision_array)
    if (collision) primitives.push_back(primitive(*collision, link));
  if (primitives.empty() && tipLink->collision) primitives.push_back(primitive(*tipLink->collision, link));
  if (primitives.empty()) throw InvalidInputError("URDF link '" + link + "' has no collision geometry");
  return ToolTip(link, std::move(primitives));
}

}  // namespace deformation_enrichment::ros_layer
