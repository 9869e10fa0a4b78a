#include "deformation_enrichment/ros/contact_tracker.hpp"

#include <tf2_eigen/tf2_eigen.h>

#include <algorithm>
#include <cmath>
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

Eigen::Isometry3d ContactTracker::linkPose(const geometry_msgs::PoseStamped& pose, const std::string& toolId,
                                           const enrichment::ToolTip& tip) {
  Eigen::Vector3d position;
  tf2::fromMsg(pose.pose.position, position);
  Eigen::Quaterniond orientation;
  tf2::fromMsg(pose.pose.orientation, orientation);
  return enrichment::toolLinkPose(position, orientation, tip, toolId);
}

void ContactTracker::updateFromToolPose(const geometry_msgs::PoseStamped& pose, const std::string& toolId,
                                        const std::string& meshFrame, const Eigen::Matrix3Xf& surface,
                                        const Eigen::Matrix3Xd& restNormals, double contactDistance,
                                        const enrichment::ToolTip& tip, const Eigen::Matrix3Xi* triangles) {
  const Eigen::Isometry3d linkToMesh = toMeshFrame(pose.header, meshFrame) * linkPose(pose, toolId, tip);
  if (surface.cols() == 0) throw InvalidInputError("no mesh state yet to find the contact of tool '" + toolId + "'");
  const enrichment::ToolProximity contact =
      enrichment::toolProximity(linkToMesh, tip, surface, contactDistance, triangles, vertexBound_);
  latestStamp_ = std::max(latestStamp_, pose.header.stamp);
  if (!contact.inContact) {
    contacts_.erase(toolId);
    return;
  }
  contacts_[toolId] = TrackedContact{toolId, contact.point, restNormals.col(contact.nearestVertex), 0.0, pose.header.stamp};
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
