#include "deformation_enrichment/ros/conversions.hpp"

#include <sensor_msgs/point_cloud2_iterator.h>

#include <string>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/polygon_triangulation.hpp"

namespace deformation_enrichment::ros_layer {
namespace {

// Byte offsets of x, y, z after checking that all three exist as float32 and the buffer is consistent.
std::array<uint32_t, 3> xyzOffsets(const sensor_msgs::PointCloud2& cloud) {
  std::array<uint32_t, 3> offsets{};
  const char* names[3] = {"x", "y", "z"};
  for (int axis = 0; axis < 3; ++axis) {
    const sensor_msgs::PointField* found = nullptr;
    for (const auto& field : cloud.fields)
      if (field.name == names[axis]) found = &field;
    if (!found) throw InvalidInputError(std::string("point cloud has no '") + names[axis] + "' field");
    if (found->datatype != sensor_msgs::PointField::FLOAT32 || found->count != 1)
      throw InvalidInputError(std::string("point cloud field '") + names[axis] + "' is not a single float32");
    if (found->offset + sizeof(float) > cloud.point_step)
      throw InvalidInputError(std::string("point cloud field '") + names[axis] + "' lies outside point_step");
    offsets[axis] = found->offset;
  }
  if (cloud.is_bigendian) throw InvalidInputError("big-endian point clouds are not supported");
  const uint64_t points = static_cast<uint64_t>(cloud.width) * cloud.height;
  if (static_cast<uint64_t>(cloud.row_step) * cloud.height != cloud.data.size() ||
      static_cast<uint64_t>(cloud.point_step) * cloud.width > cloud.row_step)
    throw InvalidInputError("point cloud data size " + std::to_string(cloud.data.size()) + " does not match " +
                            std::to_string(points) + " points of " + std::to_string(cloud.point_step) + " bytes");
  return offsets;
}

}  // namespace

Eigen::Matrix3Xf positionsFromCloud(const sensor_msgs::PointCloud2& cloud) {
  const auto offsets = xyzOffsets(cloud);
  Eigen::Matrix3Xf positions(3, static_cast<Eigen::Index>(cloud.width) * cloud.height);
  Eigen::Index index = 0;
  for (uint32_t row = 0; row < cloud.height; ++row) {
    const uint8_t* point = cloud.data.data() + static_cast<size_t>(row) * cloud.row_step;
    for (uint32_t column = 0; column < cloud.width; ++column, point += cloud.point_step, ++index) {
      for (int axis = 0; axis < 3; ++axis) std::memcpy(&positions(axis, index), point + offsets[axis], sizeof(float));
    }
  }
  return positions;
}

void writePositions(const Eigen::Matrix3Xf& positions, sensor_msgs::PointCloud2& cloud) {
  const auto offsets = xyzOffsets(cloud);
  if (static_cast<uint64_t>(cloud.width) * cloud.height != static_cast<uint64_t>(positions.cols()))
    throw InvalidInputError("cannot write " + std::to_string(positions.cols()) + " positions into a cloud of " +
                            std::to_string(static_cast<uint64_t>(cloud.width) * cloud.height) + " points");
  Eigen::Index index = 0;
  for (uint32_t row = 0; row < cloud.height; ++row) {
    uint8_t* point = cloud.data.data() + static_cast<size_t>(row) * cloud.row_step;
    for (uint32_t column = 0; column < cloud.width; ++column, point += cloud.point_step, ++index) {
      for (int axis = 0; axis < 3; ++axis) std::memcpy(point + offsets[axis], &positions(axis, index), sizeof(float));
    }
  }
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
  mesh::TriangleMesh result;
  const Eigen::Matrix3Xf positions = positionsFromCloud(message.cloud);
  if (positions.cols() == 0) throw InvalidInputError("rest mesh has no vertices");
  result.vertices = positions.cast<double>();
  result.triangles = mesh::fanTriangulate(message.polygons, result.numVertices(),
                                          [](const pcl_msgs::Vertices& p) -> const auto& { return p.vertices; });
  if (result.numTriangles() == 0) throw InvalidInputError("rest mesh has no triangles");
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

}  // namespace deformation_enrichment::ros_layer
