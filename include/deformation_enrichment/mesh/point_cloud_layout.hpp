#pragma once
// Raw point-cloud buffers as sensor_msgs/PointCloud2 and pcl::PCLPointCloud2 lay them out: width x height
// points of point_step bytes, rows row_step bytes apart, named typed fields at byte offsets inside a
// point. Described without ROS or PCL types, so the ROS adapters and the fuzz harnesses
// share one validation of untrusted buffers. Positions are float32 x, y, z.
#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace deformation_enrichment::mesh {

/// PointField datatype code of float32 (the same in sensor_msgs/PointField and pcl::PCLPointField).
constexpr std::uint8_t kFloat32Field = 7;

struct PointFieldLayout {
  std::string name;
  std::uint32_t offset = 0;   ///< bytes from the start of a point
  std::uint8_t datatype = 0;  ///< PointField datatype code
  std::uint32_t count = 1;    ///< elements of that type
};

struct PointCloudLayout {
  std::vector<PointFieldLayout> fields;
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  std::uint32_t pointStep = 0;  ///< bytes per point
  std::uint32_t rowStep = 0;    ///< bytes per row
  bool isBigEndian = false;
};

/// Byte offsets of x, y, z inside a point. Throws InvalidInputError naming the problem: a missing field,
/// one that is not a single float32 or lies outside point_step, a big-endian cloud, or a data size that
/// does not match height rows of row_step bytes holding width points of point_step bytes each.
std::array<std::uint32_t, 3> xyzOffsets(const PointCloudLayout& layout, std::size_t dataSize);

/// The x, y, z of every point, row by row (values as stored, non-finite ones included).
Eigen::Matrix3Xf decodePositions(const PointCloudLayout& layout, const std::uint8_t* data, std::size_t size);
/// The same into `positions`, whose storage is reused when it already has the size (a stream of states:
/// no allocation per state); x, y, z packed at the start of 12-byte points are copied a row at a time.
void decodePositions(const PointCloudLayout& layout, const std::uint8_t* data, std::size_t size, Eigen::Matrix3Xf& positions);

/// How far the points of `data` have moved from those of `previous`, two buffers of `size` bytes in `layout`:
/// the largest distance, or the first one of at least `enough` (the scan stops there: a simulator that is
/// still moving needs no more). NaN when a point scanned is not finite in either. Throws as xyzOffsets does.
float largestMotion(const PointCloudLayout& layout, const std::uint8_t* data, const std::uint8_t* previous, std::size_t size,
                    float enough);

/// Overwrites x, y, z of every point, leaving other fields untouched. Throws InvalidInputError as
/// xyzOffsets does, or when positions.cols() is not the number of points.
void encodePositions(const Eigen::Matrix3Xf& positions, const PointCloudLayout& layout, std::uint8_t* data,
                     std::size_t size);

}  // namespace deformation_enrichment::mesh
