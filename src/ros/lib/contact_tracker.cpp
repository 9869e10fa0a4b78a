#include "deformation_enrichment/ros/contact_tracker.hpp"

#include <tf2_eigen/tf2_eigen.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::ros_layer {

Eigen::Isometry3d ContactTracker::toMeshFrame(const std_msgs::Header& header, const std::string& meshFrame) const {
  // An empty frame means "already in the mesh frame" (hand-written test publishers often leave it empty).
  if (header.frame_id.empty() || header.frame_id == meshFrame) return Eigen::Isometry3d::Identity();
  try {
    return tf2::transformToEigen(tf_.lookupTransform(meshFrame, header.frame_id, header.stamp));
  } catch (const tf2::TransformException& e) {
    throw InvalidInputError("cannot transform contact from frame '" + header.frame_id + "' to mesh frame '" +
                            meshFrame + "': " + e.what());
  }
}

void ContactTracker::updateFromArray(const ToolContactArray& message, const std::string& meshFrame) {
  std::map<std::string, TrackedContact> fromArray;
  for (const auto& contact : message.contacts) {
    if (!contact.in_contact) continue;
    Eigen::Vector3d position, normal;
    tf2::fromMsg(contact.position, position);
    tf2::fromMsg(contact.normal, normal);
    if (!position.allFinite() || !normal.allFinite() || !std::isfinite(contact.force))
      throw InvalidInputError("contact of tool '" + contact.tool_id + "' has a non-finite position, normal or force");
    std_msgs::Header header = contact.header;
    if (header.frame_id.empty()) header.frame_id = message.header.frame_id;
    if (header.stamp.isZero()) header.stamp = message.header.stamp;
    const Eigen::Isometry3d transform = toMeshFrame(header, meshFrame);
    const double length = normal.norm();
    TrackedContact tracked{contact.tool_id, transform * position,
                           length > 0.0 ? Eigen::Vector3d(transform.linear() * normal / length) : Eigen::Vector3d::Zero(),
                           contact.force, header.stamp};
    fromArray[contact.tool_id] = tracked;
  }
  // Tools absent from the array (or not in contact) lifted off.
  for (auto it = contacts_.begin(); it != contacts_.end();) {
    it = fromArray.count(it->first) ? std::next(it) : contacts_.erase(it);
  }
  for (auto& [id, contact] : fromArray) contacts_[id] = contact;
  latestStamp_ = std::max(latestStamp_, message.header.stamp);
}

Eigen::Isometry3d ContactTracker::linkPose(const geometry_msgs::PoseStamped& pose, const std::string& toolId, const ToolTip& tip) {
  Eigen::Vector3d position;
  tf2::fromMsg(pose.pose.position, position);
  Eigen::Quaterniond orientation;
  tf2::fromMsg(pose.pose.orientation, orientation);
  if (!position.allFinite() || !orientation.coeffs().allFinite())
    throw InvalidInputError("tool pose of '" + toolId + "' is not finite");
  // A point tip ignores the orientation (a position-only source may leave the quaternion zero).
  if (tip.isPoint()) orientation = Eigen::Quaterniond::Identity();
  else if (std::abs(orientation.norm() - 1.0) > 1e-3)
    throw InvalidInputError("tool pose of '" + toolId + "' has no valid orientation (quaternion norm " +
                            std::to_string(orientation.norm()) + ")");
  return Eigen::Translation3d(position) * orientation.normalized();
}

void ContactTracker::updateFromToolPose(const geometry_msgs::PoseStamped& pose, const std::string& toolId,
                                        const std::string& meshFrame, const Eigen::Matrix3Xf& surface,
                                        const Eigen::Matrix3Xd& restNormals, double contactDistance, const ToolTip& tip,
                                        const Eigen::Matrix3Xi* triangles) {
  const Eigen::Isometry3d linkToMesh = toMeshFrame(pose.header, meshFrame) * linkPose(pose, toolId, tip);
  const Eigen::Isometry3d meshToLink = linkToMesh.inverse();
  if (surface.cols() == 0) throw InvalidInputError("no mesh state yet to find the contact of tool '" + toolId + "'");
  // Lower bounds |v - c| - R from the tip's bounding ball (vectorised, float; 1 um slack for rounding),
  // so the exact signed distance is evaluated only where it can matter.
  const Eigen::Vector3f centre = (linkToMesh * tip.boundCentre()).cast<float>();
  vertexBound_ = (surface.colwise() - centre).colwise().norm().array() - static_cast<float>(tip.boundRadius() + 1e-6);
  Eigen::Index nearest = 0;
  vertexBound_.minCoeff(&nearest);
  double distance = tip.signedDistance(meshToLink * Eigen::Vector3d(surface.col(nearest).cast<double>()));
  for (Eigen::Index v = 0; v < surface.cols(); ++v) {
    if (vertexBound_[v] >= distance) continue;
    const double d = tip.signedDistance(meshToLink * Eigen::Vector3d(surface.col(v).cast<double>()));
    if (d < distance) {
      distance = d;
      nearest = v;
    }
  }
  Eigen::Vector3d point = surface.col(nearest).cast<double>();
  Eigen::Index normalVertex = nearest;
  if (triangles != nullptr) {
    if (triangles->size() > 0 && (triangles->minCoeff() < 0 || triangles->maxCoeff() >= surface.cols()))
      throw InvalidInputError("the surface triangles reference vertices the mesh state does not have");
    const int* index = triangles->data();
    const float* bound = vertexBound_.data();
    for (Eigen::Index t = 0; t < triangles->cols(); ++t) {
      const Eigen::Vector3i f(index[3 * t], index[3 * t + 1], index[3 * t + 2]);
      // A triangle point within the contact distance (or closer than the best so far) needs a vertex within
      // that plus the triangle's longest edge: the signed distance is 1-Lipschitz.
      const float gap = std::min({bound[f[0]], bound[f[1]], bound[f[2]]}) - static_cast<float>(std::min(contactDistance, distance));
      if (gap > 0.0f) {
        const float longest = std::max({(surface.col(f[1]) - surface.col(f[0])).squaredNorm(),
                                        (surface.col(f[2]) - surface.col(f[1])).squaredNorm(),
                                        (surface.col(f[0]) - surface.col(f[2])).squaredNorm()});
        if (longest < gap * gap) continue;
      }
      const Eigen::Vector3d a = surface.col(f[0]).cast<double>(), b = surface.col(f[1]).cast<double>(),
                            c = surface.col(f[2]).cast<double>();
      Eigen::Vector3d closest;
      const double d = tip.triangleDistance(meshToLink * a, meshToLink * b, meshToLink * c, &closest);
      if (d < distance) {
        distance = d;
        point = linkToMesh * closest;
        normalVertex = f[0];
        for (int k = 1; k < 3; ++k)
          if ((surface.col(f[k]).cast<double>() - point).squaredNorm() <
              (surface.col(normalVertex).cast<double>() - point).squaredNorm())
            normalVertex = f[k];
      }
    }
  }
  latestStamp_ = std::max(latestStamp_, pose.header.stamp);
  if (distance > contactDistance) {
    contacts_.erase(toolId);
    return;
  }
  // A point tip without triangles is in contact by its nearest vertex, but the contact is the tip itself: the
  // enricher puts it on its nearest surface point, so it does not jump from vertex to vertex as the tool slides.
  if (tip.isPoint() && triangles == nullptr) point = linkToMesh.translation();
  contacts_[toolId] = TrackedContact{toolId, point, restNormals.col(normalVertex), 0.0, pose.header.stamp};
}

std::vector<TrackedContact> ContactTracker::active(const ros::Time& now) {
  if (now + ros::Duration(1.0) < latestStamp_) {  // time jumped backwards: a bag started over
    contacts_.clear();
    latestStamp_ = ros::Time();
  }
  std::vector<TrackedContact> result;
  for (const auto& [id, contact] : contacts_) {
    if (contact.stamp.isZero() || now - contact.stamp <= staleAfter_) result.push_back(contact);
  }
  return result;
}

}  // namespace deformation_enrichment::ros_layer
