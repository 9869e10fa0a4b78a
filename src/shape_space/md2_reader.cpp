#include "deformation_enrichment/shape_space/md2_reader.hpp"

#include <array>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>

#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::shape_space {
namespace {

// The MD2 header: magic "IDP2", version 8, then counts and byte offsets (all little-endian int32).
struct Md2Header {
  int32_t skinWidth, skinHeight, frameSize, numSkins, numVertices, numTexCoords, numTriangles,
      numGlCommands, numFrames, offsetSkins, offsetTexCoords, offsetTriangles, offsetFrames,
      offsetGlCommands, offsetEnd;
};

int32_t readInt32(const std::vector<unsigned char>& bytes, size_t offset) {
  uint32_t v = uint32_t(bytes[offset]) | (uint32_t(bytes[offset + 1]) << 8) |
               (uint32_t(bytes[offset + 2]) << 16) | (uint32_t(bytes[offset + 3]) << 24);
  int32_t out;
  std::memcpy(&out, &v, sizeof(out));
  return out;
}

float readFloat32(const std::vector<unsigned char>& bytes, size_t offset) {
  const int32_t bits = readInt32(bytes, offset);
  float out;
  std::memcpy(&out, &bits, sizeof(out));
  return out;
}

int readInt16(const std::vector<unsigned char>& bytes, size_t offset) {
  return int16_t(uint16_t(bytes[offset]) | (uint16_t(bytes[offset + 1]) << 8));
}

}  // namespace

Md2Animation readMd2(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError("cannot open MD2 file '" + path + "'");
  const std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto fail = [&](const std::string& what) { throw IoError("MD2 file '" + path + "': " + what); };
  if (bytes.size() < 68) fail("shorter than the 68-byte header");
  if (std::memcmp(bytes.data(), "IDP2", 4) != 0) fail("bad magic (expected IDP2)");
  if (readInt32(bytes, 4) != 8) fail("unsupported version " + std::to_string(readInt32(bytes, 4)));
  Md2Header h{};
  int32_t* fields = &h.skinWidth;
  for (int k = 0; k < 15; ++k) fields[k] = readInt32(bytes, 8 + 4 * size_t(k));
  if (h.numVertices <= 0 || h.numTriangles <= 0 || h.numFrames <= 0) fail("no vertices, triangles or frames");
  if (int64_t(h.frameSize) != 40 + 4 * int64_t(h.numVertices)) fail("frame size does not match the vertex count");
  const auto inside = [&](int64_t offset, int64_t count, int64_t stride) {
    return offset >= 68 && count >= 0 && offset + count * stride <= int64_t(bytes.size());
  };
  if (!inside(h.offsetTriangles, h.numTriangles, 12)) fail("triangle block outside the file (truncated?)");
  if (!inside(h.offsetFrames, h.numFrames, h.frameSize)) fail("frame block outside the file (truncated?)");

  // Triangles: 3 vertex indices then 3 texture indices (int16 each). Drop those repeating a vertex.
  std::vector<std::array<int, 3>> triangles;
  std::vector<int> used(size_t(h.numVertices), 0);
  for (int t = 0; t < h.numTriangles; ++t) {
    const size_t base = size_t(h.offsetTriangles) + 12 * size_t(t);
    std::array<int, 3> tri{readInt16(bytes, base), readInt16(bytes, base + 2), readInt16(bytes, base + 4)};
    for (int k = 0; k < 3; ++k)
      if (tri[k] < 0 || tri[k] >= h.numVertices) fail("triangle " + std::to_string(t) + " has a bad vertex index");
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2]) continue;
    triangles.push_back(tri);
    for (int k = 0; k < 3; ++k) used[size_t(tri[k])] = 1;
  }
  if (triangles.empty()) fail("every triangle repeats a vertex");
  std::vector<int> newIndex(size_t(h.numVertices), -1);
  int numUsed = 0;
  for (int v = 0; v < h.numVertices; ++v)
    if (used[size_t(v)]) newIndex[size_t(v)] = numUsed++;

  Eigen::Matrix3Xi triangleMatrix(3, Eigen::Index(triangles.size()));
  for (size_t t = 0; t < triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) triangleMatrix(k, Eigen::Index(t)) = newIndex[size_t(triangles[t][size_t(k)])];

  Md2Animation animation;
  for (int f = 0; f < h.numFrames; ++f) {
    const size_t base = size_t(h.offsetFrames) + size_t(h.frameSize) * size_t(f);
    Eigen::Vector3d scale, translate;
    for (int k = 0; k < 3; ++k) {
      scale[k] = readFloat32(bytes, base + 4 * size_t(k));
      translate[k] = readFloat32(bytes, base + 12 + 4 * size_t(k));
    }
    if (!scale.allFinite() || !translate.allFinite()) fail("frame " + std::to_string(f) + " has a non-finite scale");
    const char* name = reinterpret_cast<const char*>(bytes.data() + base + 24);
    animation.frameNames.emplace_back(name, strnlen(name, 16));
    mesh::TriangleMesh frame;
    frame.triangles = triangleMatrix;
    frame.vertices.resize(3, numUsed);
    for (int v = 0; v < h.numVertices; ++v) {
      if (newIndex[size_t(v)] < 0) continue;
      const size_t vb = base + 40 + 4 * size_t(v);
      for (int k = 0; k < 3; ++k)  // position = byte * scale + translate (the 4th byte is a normal index)
        frame.vertices(k, newIndex[size_t(v)]) = double(bytes[vb + size_t(k)]) * scale[k] + translate[k];
    }
    animation.frames.push_back(std::move(frame));
  }
  return animation;
}

}  // namespace deformation_enrichment::shape_space
