#include "deformation_enrichment/enrichment/tool_proximity.hpp"

#include <algorithm>
#include <cmath>

#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::enrichment {

Eigen::Isometry3d toolLinkPose(const Eigen::Vector3d& position, const Eigen::Quaterniond& orientation, const ToolTip& tip,
                               const std::string& toolId) {
  if (!position.allFinite() || !orientation.coeffs().allFinite())
    throw InvalidInputError("tool pose of '" + toolId + "' is not finite");
  if (tip.isPoint()) return Eigen::Isometry3d(Eigen::Translation3d(position));
  if (std::abs(orientation.norm() - 1.0) > 1e-3)
    throw InvalidInputError("tool pose of '" + toolId + "' has no valid orientation (quaternion norm " +
                            std::to_string(orientation.norm()) + ")");
  return Eigen::Translation3d(position) * orientation.normalized();
}

namespace {

// The nearest triangle point of the tip among the triangles that can beat `best` (or reach the contact
// distance), updating `best` in place.
void nearestOnTriangles(const Eigen::Isometry3d& linkToMesh, const ToolTip& tip, const Eigen::Matrix3Xf& vertices,
                        double contactDistance, const Eigen::Matrix3Xi& triangles, const Eigen::ArrayXf& bound,
                        ToolProximity& best) {
  if (triangles.size() > 0 && (triangles.minCoeff() < 0 || triangles.maxCoeff() >= vertices.cols()))
    throw InvalidInputError("the surface triangles reference vertices the mesh state does not have");
  const Eigen::Isometry3d meshToLink = linkToMesh.inverse();
  const int* index = triangles.data();
  for (Eigen::Index t = 0; t < triangles.cols(); ++t) {
    const Eigen::Vector3i f(index[3 * t], index[3 * t + 1], index[3 * t + 2]);
    // A triangle point within the contact distance (or closer than the best so far) needs a vertex within
    // that plus the triangle's longest edge: the signed distance is 1-Lipschitz.
    const float gap = std::min({bound[f[0]], bound[f[1]], bound[f[2]]}) - static_cast<float>(std::min(contactDistance, best.distance));
    if (gap > 0.0f) {
      const float longest = std::max({(vertices.col(f[1]) - vertices.col(f[0])).squaredNorm(),
                                      (vertices.col(f[2]) - vertices.col(f[1])).squaredNorm(),
                                      (vertices.col(f[0]) - vertices.col(f[2])).squaredNorm()});
      if (longest < gap * gap) continue;
    }
    const Eigen::Vector3d a = vertices.col(f[0]).cast<double>(), b = vertices.col(f[1]).cast<double>(),
                          c = vertices.col(f[2]).cast<double>();
    Eigen::Vector3d closest;
    const double d = tip.triangleDistance(meshToLink * a, meshToLink * b, meshToLink * c, &closest);
    if (d < best.distance) {
      best.distance = d;
      best.point = linkToMesh * closest;
      best.nearestVertex = f[0];
      for (int k = 1; k < 3; ++k)
        if ((vertices.col(f[k]).cast<double>() - best.point).squaredNorm() <
            (vertices.col(best.nearestVertex).cast<double>() - best.point).squaredNorm())
          best.nearestVertex = f[k];
    }
  }
}

}  // namespace

ToolProximity toolProximity(const Eigen::Isometry3d& linkToMesh, const ToolTip& tip, const Eigen::Matrix3Xf& vertices,
                            double contactDistance, const Eigen::Matrix3Xi* triangles, Eigen::ArrayXf& scratch) {
  if (vertices.cols() == 0) throw InvalidInputError("no surface vertices to find the tool's contact on");
  const Eigen::Isometry3d meshToLink = linkToMesh.inverse();
  // Lower bounds |v - c| - R from the tip's bounding ball (vectorised, float; 1 um slack for rounding), so
  // the exact signed distance is evaluated only where it can matter.
  const Eigen::Vector3f centre = (linkToMesh * tip.boundCentre()).cast<float>();
  scratch = (vertices.colwise() - centre).colwise().norm().array() - static_cast<float>(tip.boundRadius() + 1e-6);
  ToolProximity best;
  scratch.minCoeff(&best.nearestVertex);
  best.distance = tip.signedDistance(meshToLink * Eigen::Vector3d(vertices.col(best.nearestVertex).cast<double>()));
  for (Eigen::Index v = 0; v < vertices.cols(); ++v) {
    if (scratch[v] >= best.distance) continue;
    const double d = tip.signedDistance(meshToLink * Eigen::Vector3d(vertices.col(v).cast<double>()));
    if (d < best.distance) {
      best.distance = d;
      best.nearestVertex = v;
    }
  }
  best.point = vertices.col(best.nearestVertex).cast<double>();
  if (triangles != nullptr) nearestOnTriangles(linkToMesh, tip, vertices, contactDistance, *triangles, scratch, best);
  best.inContact = best.distance <= contactDistance;
  // A point tip measured against the vertices touches at the tip itself.
  if (tip.isPoint() && triangles == nullptr) best.point = linkToMesh.translation();
  return best;
}

}  // namespace deformation_enrichment::enrichment
