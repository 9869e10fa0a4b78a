#pragma once
// Conversions between ROS messages and core types. Mesh states travel as PointCloud2 with float32
// x, y, z fields (one point per rest vertex, fixed order); topology travels once as pcl_msgs/PolygonMesh.
#include <Eigen/Core>
#include <geometry_msgs/PoseStamped.h>
#include <pcl_msgs/PolygonMesh.h>
#include <sensor_msgs/PointCloud2.h>

#include "deformation_enrichment/mesh/triangle_mesh.hpp"

namespace deformation_enrichment::ros_layer {

/// Reads the x, y, z float32 fields (mesh::decodePositions). Throws InvalidInputError naming a missing or
/// mistyped field or a data buffer that does not match width, height and point_step.
Eigen::Matrix3Xf positionsFromCloud(const sensor_msgs::PointCloud2& cloud);
/// The same into `positions`, reusing its storage when the size is the same.
void positionsFromCloud(const sensor_msgs::PointCloud2& cloud, Eigen::Matrix3Xf& positions);

/// mesh::largestMotion of `cloud` since `previous`. Throws InvalidInputError when either layout is not one
/// positionsFromCloud accepts, or the two differ.
float largestMotion(const sensor_msgs::PointCloud2& cloud, const sensor_msgs::PointCloud2& previous, float enough);

/// Overwrites the x, y, z fields of `cloud` (which must already have the layout positionsFromCloud
/// accepts and positions.cols() points), leaving every other field and the header untouched.
void writePositions(const Eigen::Matrix3Xf& positions, sensor_msgs::PointCloud2& cloud);

/// A dense, unorganised x y z float32 cloud.
sensor_msgs::PointCloud2 cloudFromPositions(const Eigen::Matrix3Xf& positions, const std_msgs::Header& header);

/// mesh::triangleMeshFromCloud, then mesh::validate(..., false). Throws InvalidInputError if the message
/// is empty, its polygons reference missing vertices, it has no triangle or a triangle repeats a vertex.
mesh::TriangleMesh triangleMeshFromMessage(const pcl_msgs::PolygonMesh& message);

pcl_msgs::PolygonMesh messageFromTriangleMesh(const mesh::TriangleMesh& mesh, const std_msgs::Header& header);

/// A pose at `position` with the identity orientation (a tool sphere's centre, a point tip).
geometry_msgs::PoseStamped poseAt(const Eigen::Vector3d& position, const std_msgs::Header& header);

}  // namespace deformation_enrichment::ros_layer
