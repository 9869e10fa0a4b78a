#pragma once
// The byte format of the point-cloud harnesses' inputs (and of the seeds fuzz_make_seeds writes): a
// PointCloud2 / PolygonMesh message's layout, optional polygons, then the data buffer. Little-endian:
//   u32 width, u32 height, u32 point_step, u32 row_step, u8 is_bigendian, u8 field count,
//   per field: u8 name length, name, u32 offset, u8 datatype, u32 count;
//   with polygons: u16 polygon count, per polygon: u8 corner count, u32 corners;
//   the rest: data.
#include <cstdint>
#include <cstring>
#include <optional>
#include <vector>

#include "deformation_enrichment/mesh/point_cloud_layout.hpp"

namespace deformation_enrichment::fuzz {

struct CloudInput {
  mesh::PointCloudLayout layout;
  std::vector<std::vector<std::uint32_t>> polygons;
  std::vector<std::uint8_t> data;
};

namespace detail {
class ByteReader {
public:
  ByteReader(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}
  template <class T>
  bool take(T& value) {
    if (size_ - used_ < sizeof(T)) return false;
    std::memcpy(&value, data_ + used_, sizeof(T));
    used_ += sizeof(T);
    return true;
  }
  bool take(std::string& text, std::size_t length) {
    if (size_ - used_ < length) return false;
    text.assign(reinterpret_cast<const char*>(data_ + used_), length);
    used_ += length;
    return true;
  }
  std::vector<std::uint8_t> rest() const { return {data_ + used_, data_ + size_}; }

private:
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t used_ = 0;
};

template <class T>
void put(std::vector<std::uint8_t>& out, T value) {
  const auto* bytes = reinterpret_cast<const std::uint8_t*>(&value);
  out.insert(out.end(), bytes, bytes + sizeof(T));
}
}  // namespace detail

/// Nothing when the input ends inside the layout or polygons (memory stays bounded by the input).
inline std::optional<CloudInput> decodeCloudInput(const std::uint8_t* data, std::size_t size, bool withPolygons) {
  detail::ByteReader in(data, size);
  CloudInput c;
  mesh::PointCloudLayout& l = c.layout;
  std::uint8_t bigEndian = 0, fields = 0;
  if (!in.take(l.width) || !in.take(l.height) || !in.take(l.pointStep) || !in.take(l.rowStep) || !in.take(bigEndian) ||
      !in.take(fields))
    return std::nullopt;
  l.isBigEndian = bigEndian != 0;
  l.fields.resize(fields);
  for (mesh::PointFieldLayout& f : l.fields) {
    std::uint8_t length = 0;
    if (!in.take(length) || !in.take(f.name, length) || !in.take(f.offset) || !in.take(f.datatype) || !in.take(f.count))
      return std::nullopt;
  }
  std::uint16_t polygons = 0;
  if (withPolygons && !in.take(polygons)) return std::nullopt;
  c.polygons.resize(polygons);
  for (auto& polygon : c.polygons) {
    std::uint8_t corners = 0;
    if (!in.take(corners)) return std::nullopt;
    polygon.resize(corners);
    for (std::uint32_t& corner : polygon)
      if (!in.take(corner)) return std::nullopt;
  }
  c.data = in.rest();
  return c;
}

inline std::vector<std::uint8_t> encodeCloudInput(const CloudInput& c, bool withPolygons) {
  std::vector<std::uint8_t> out;
  const mesh::PointCloudLayout& l = c.layout;
  detail::put(out, l.width);
  detail::put(out, l.height);
  detail::put(out, l.pointStep);
  detail::put(out, l.rowStep);
  detail::put(out, static_cast<std::uint8_t>(l.isBigEndian));
  detail::put(out, static_cast<std::uint8_t>(l.fields.size()));
  for (const mesh::PointFieldLayout& f : l.fields) {
    detail::put(out, static_cast<std::uint8_t>(f.name.size()));
    out.insert(out.end(), f.name.begin(), f.name.end());
    detail::put(out, f.offset);
    detail::put(out, f.datatype);
    detail::put(out, f.count);
  }
  if (withPolygons) {
    detail::put(out, static_cast<std::uint16_t>(c.polygons.size()));
    for (const auto& polygon : c.polygons) {
      detail::put(out, static_cast<std::uint8_t>(polygon.size()));
      for (const std::uint32_t corner : polygon) detail::put(out, corner);
    }
  }
  out.insert(out.end(), c.data.begin(), c.data.end());
  return out;
}

}  // namespace deformation_enrichment::fuzz
