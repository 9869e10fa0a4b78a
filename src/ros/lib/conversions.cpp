#include "deformation_enrichment/ros/conversions.hpp"

#include <sensor_msgs/point_cloud2_iterator.h>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/point_cloud_layout.hpp"
#include "deformation_enrichment/mesh/triangle_mesh_from_cloud.hpp"

namespace deformation_enrichment::ros_layer {
namespace {

// The message's layout in core terms (the decoding and its validation live in mesh/point_cloud_layout).
mesh::PointCloudLayout layoutOf(const sensor_msgs::PointCloud2& cloud) {
  mesh::PointCloudLayout layout;
  layout.fields.reserve(cloud.fields.size());
  for (const auto& field : cloud.fields) layout.fields.push_back({field.name, field.offset, field.datatype, field.count});
  layout.width = cloud.width;
  layout.height = cloud.height;
  layout.pointStep = cloud.point_step;
  layout.rowStep = cloud.row_step;
  layout.isBigEndian = cloud.is_bigendian;
  return layout;
}

}  // namespace

Eigen::Matrix3Xf positionsFromCloud(const sensor_msgs::PointCloud2& cloud) {
  return mesh::decodePositions(layoutOf(cloud), cloud.data.data(), cloud.data.size());
}

void positionsFromCloud(const sensor_msgs::PointCloud2& cloud, Eigen::Matrix3Xf& positions) {
  mesh::decodePositions(layoutOf(cloud), cloud.data.data(), cloud.data.size(), positions);
}

float largestMotion(const sensor_msgs::PointCloud2& cloud, const sensor_msgs::PointCloud2& previous, float enough) {
  const mesh::PointCloudLayout layout = layoutOf(cloud), before = layoutOf(previous);
  if (mesh::xyzOffsets(layout, cloud.data.size()) != mesh::xyzOffsets(before, previous.data.size()) ||
      layout.width != before.width || layout.height != before.height || layout.pointStep != before.pointStep ||
      layout.rowStep != before.rowStep)
    throw InvalidInputError("point cloud layout changed between two states");
  return mesh::largestMotion(layout, cloud.data.data(), previous.data.data(), cloud.data.size(), enough);
}

void writePositions(const Eigen::Matrix3Xf& positions, sensor_msgs::PointCloud2& cloud) {
  mesh::encodePositions(positions, layoutOf(cloud), cloud.data.data(), cloud.data.size());
}

sensor_msgs::PointCloud2 cloudFromPositions(const Eigen::Matrix3Xf& positions, const std_msgs::Header& header) {
  sensor_msgs::PointCloud2 cloud;
  cloud.header = header;
  sensor_msgs::PointCloud2Modifier modifier(cloud);
  modifier.setPointCloud2FieldsByString(1, "xyz");
  modifier.resize(static_cast<size_t>(positions.cols()));
  cloud.is_dense = true;
  writePositions(positions, cloud);
  return cloud;
}

mesh::TriangleMesh triangleMeshFromMessage(const pcl_msgs::PolygonMesh& message) {
  const sensor_msgs::PointCloud2& cloud = message.cloud;
  mesh::TriangleMesh result =
      mesh::triangleMeshFromCloud(layoutOf(cloud), cloud.data.data(), cloud.data.size(), message.polygons,
                                  [](const pcl_msgs::Vertices& p) -> const auto& { return p.vertices; });
  mesh::validate(result, false);
  return result;
}

pcl_msgs::PolygonMesh messageFromTriangleMesh(const mesh::TriangleMesh& mesh, const std_msgs::Header& header) {
  pcl_msgs::PolygonMesh message;
  message.header = header;
  message.cloud = cloudFromPositions(mesh.vertices.cast<float>(), header);
  message.polygons.resize(static_cast<size_t>(mesh.numTriangles()));
  for (Eigen::Index t = 0; t < mesh.numTriangles(); ++t)
    for (int k = 0; k < 3; ++k)
      message.polygons[static_cast<size_t>(t)].vertices.push_back(static_cast<uint32_t>(mesh.triangles(k, t)));
  return message;
}

geometry_msgs::PoseStamped poseAt(const Eigen::Vector3d& position, const std_msgs::Header& header) {
  geometry_msgs::PoseStamped pose;
  pose.header = header;
  pose.pose.position.x = position.x();
  pose.pose.position.y = position.y();
  pose.pose.position.z = position.z();
  pose.pose.orientation.w = 1.0;
  return pose;
}

}  // namespace deformation_enrichment::ros_layer
