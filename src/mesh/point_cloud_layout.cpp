#include "deformation_enrichment/mesh/point_cloud_layout.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::mesh {

std::array<std::uint32_t, 3> xyzOffsets(const PointCloudLayout& layout, std::size_t dataSize) {
  std::array<std::uint32_t, 3> offsets{};
  const char* names[3] = {"x", "y", "z"};
  for (int axis = 0; axis < 3; ++axis) {
    const PointFieldLayout* found = nullptr;
    for (const auto& field : layout.fields)
      if (field.name == names[axis]) found = &field;
    if (!found) throw InvalidInputError(std::string("point cloud has no '") + names[axis] + "' field");
    if (found->datatype != kFloat32Field || found->count != 1)
      throw InvalidInputError(std::string("point cloud field '") + names[axis] + "' is not a single float32");
    if (found->offset + sizeof(float) > layout.pointStep)
      throw InvalidInputError(std::string("point cloud field '") + names[axis] + "' lies outside point_step");
    offsets[axis] = found->offset;
  }
  if (layout.isBigEndian) throw InvalidInputError("big-endian point clouds are not supported");
  const std::uint64_t points = static_cast<std::uint64_t>(layout.width) * layout.height;
  if (static_cast<std::uint64_t>(layout.rowStep) * layout.height != dataSize ||
      static_cast<std::uint64_t>(layout.pointStep) * layout.width > layout.rowStep)
    throw InvalidInputError("point cloud data size " + std::to_string(dataSize) + " does not match " +
                            std::to_string(points) + " points of " + std::to_string(layout.pointStep) + " bytes");
  return offsets;
}

namespace {

// x, y, z as three consecutive floats at the start of a point: one copy per point (or per row of points).
bool packedXyz(const std::array<std::uint32_t, 3>& offsets) { return offsets[0] == 0 && offsets[1] == 4 && offsets[2] == 8; }

}  // namespace

void decodePositions(const PointCloudLayout& layout, const std::uint8_t* data, std::size_t size, Eigen::Matrix3Xf& positions) {
  const auto offsets = xyzOffsets(layout, size);
  positions.resize(3, static_cast<Eigen::Index>(layout.width) * layout.height);  // keeps its storage for the same size
  // Without points the rows are empty: a lying height of 4e9 must not cost 4e9 loop turns.
  if (positions.cols() == 0) return;
  const bool packed = packedXyz(offsets);
  Eigen::Index index = 0;
  for (std::uint32_t row = 0; row < layout.height; ++row) {
    const std::uint8_t* point = data + static_cast<std::size_t>(row) * layout.rowStep;
    if (packed && layout.pointStep == 3 * sizeof(float)) {  // a row is one block of floats
      std::memcpy(&positions(0, index), point, 3 * sizeof(float) * layout.width);
      index += layout.width;
      continue;
    }
    for (std::uint32_t column = 0; column < layout.width; ++column, point += layout.pointStep, ++index) {
      if (packed) std::memcpy(&positions(0, index), point, 3 * sizeof(float));
      else
        for (int axis = 0; axis < 3; ++axis) std::memcpy(&positions(axis, index), point + offsets[axis], sizeof(float));
    }
  }
}

float largestMotion(const PointCloudLayout& layout, const std::uint8_t* data, const std::uint8_t* previous, std::size_t size,
                    float enough) {
  const auto offsets = xyzOffsets(layout, size);
  const float enoughSquared = enough * enough;
  float largest = 0.0f;
  for (std::uint32_t row = 0; row < layout.height; ++row) {
    const std::size_t start = static_cast<std::size_t>(row) * layout.rowStep;
    for (std::uint32_t column = 0; column < layout.width; ++column) {
      const std::size_t point = start + static_cast<std::size_t>(column) * layout.pointStep;
      float squared = 0.0f;
      for (int axis = 0; axis < 3; ++axis) {
        float now, before;
        std::memcpy(&now, data + point + offsets[axis], sizeof(float));
        std::memcpy(&before, previous + point + offsets[axis], sizeof(float));
        squared += (now - before) * (now - before);
      }
      if (!std::isfinite(squared)) return std::numeric_limits<float>::quiet_NaN();
      if (squared >= enoughSquared) return std::sqrt(squared);
      largest = std::max(largest, squared);
    }
  }
  return std::sqrt(largest);
}

Eigen::Matrix3Xf decodePositions(const PointCloudLayout& layout, const std::uint8_t* data, std::size_t size) {
  Eigen::Matrix3Xf positions;
  decodePositions(layout, data, size, positions);
  return positions;
}

void encodePositions(const Eigen::Matrix3Xf& positions, const PointCloudLayout& layout, std::uint8_t* data,
                     std::size_t size) {
  const auto offsets = xyzOffsets(layout, size);
  const std::uint64_t points = static_cast<std::uint64_t>(layout.width) * layout.height;
  if (points != static_cast<std::uint64_t>(positions.cols()))
    throw InvalidInputError("cannot write " + std::to_string(positions.cols()) + " positions into a cloud of " +
                            std::to_string(points) + " points");
  if (points == 0) return;  // as in decodePositions
  const bool packed = packedXyz(offsets);
  Eigen::Index index = 0;
  for (std::uint32_t row = 0; row < layout.height; ++row) {
    std::uint8_t* point = data + static_cast<std::size_t>(row) * layout.rowStep;
    if (packed && layout.pointStep == 3 * sizeof(float)) {
      std::memcpy(point, &positions(0, index), 3 * sizeof(float) * layout.width);
      index += layout.width;
      continue;
    }
    for (std::uint32_t column = 0; column < layout.width; ++column, point += layout.pointStep, ++index) {
      if (packed) std::memcpy(point, &positions(0, index), 3 * sizeof(float));
      else
        for (int axis = 0; axis < 3; ++axis) std::memcpy(point + offsets[axis], &positions(axis, index), sizeof(float));
    }
  }
}

}  // namespace deformation_enrichment::mesh
