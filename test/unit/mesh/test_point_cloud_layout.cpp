// Decoding of raw point-cloud buffers (the ROS-free half of ros_layer::positionsFromCloud and
// triangleMeshFromMessage): valid layouts round-trip, every inconsistency is named.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/point_cloud_layout.hpp"
#include "deformation_enrichment/mesh/triangle_mesh_from_cloud.hpp"
#include "../expect_error.hpp"

namespace de = deformation_enrichment;
namespace mesh = deformation_enrichment::mesh;

namespace {

// x y z float32 plus an rgb field in between (as PCL's PointXYZRGB-like clouds have), 16-byte points,
// `width` x `height` points with `padding` spare bytes at the end of every row.
struct Cloud {
  mesh::PointCloudLayout layout;
  std::vector<std::uint8_t> data;
};

Cloud makeCloud(std::uint32_t width, std::uint32_t height, std::uint32_t padding = 0) {
  Cloud c;
  c.layout.fields = {{"x", 0, mesh::kFloat32Field, 1}, {"rgb", 4, mesh::kFloat32Field, 1},
                     {"y", 8, mesh::kFloat32Field, 1}, {"z", 12, mesh::kFloat32Field, 1}};
  c.layout.width = width;
  c.layout.height = height;
  c.layout.pointStep = 16;
  c.layout.rowStep = 16 * width + padding;
  c.data.assign(static_cast<std::size_t>(c.layout.rowStep) * height, 0xAB);
  return c;
}

Eigen::Matrix3Xf ramp(Eigen::Index n) {
  Eigen::Matrix3Xf p(3, n);
  for (Eigen::Index i = 0; i < p.size(); ++i) p.data()[i] = 0.5f * static_cast<float>(i) - 1.0f;
  return p;
}

void expectInvalid(const Cloud& c, const std::string& fragment) {
  expectErrorContaining<de::InvalidInputError>([&] { mesh::decodePositions(c.layout, c.data.data(), c.data.size()); },
                                               fragment);
}

}  // namespace

TEST(PointCloudLayout, EncodeDecodeRoundTripKeepsOtherFieldsAndRowPadding) {
  Cloud c = makeCloud(3, 2, 5);
  const Eigen::Matrix3Xf p = ramp(6);
  mesh::encodePositions(p, c.layout, c.data.data(), c.data.size());
  EXPECT_EQ(mesh::decodePositions(c.layout, c.data.data(), c.data.size()), p);
  float rgb = 0.0f;
  std::memcpy(&rgb, c.data.data() + c.layout.rowStep + 16 + 4, sizeof rgb);  // row 1, point 1
  const std::uint8_t untouched[4] = {0xAB, 0xAB, 0xAB, 0xAB};
  EXPECT_EQ(std::memcmp(&rgb, untouched, 4), 0);
  EXPECT_EQ(c.data[c.layout.rowStep - 1], 0xAB);  // padding
  EXPECT_THROW(mesh::encodePositions(ramp(5), c.layout, c.data.data(), c.data.size()), de::InvalidInputError);
}

TEST(PointCloudLayout, PackedXyzRoundTripsRowByRowWithPaddingAndPaddedPoints) {
  // x y z at the start of 12-byte points (copied a row at a time) and of 16-byte points (a point at a time),
  // both with row padding, decoded into a reused matrix.
  for (const std::uint32_t step : {12u, 16u}) {
    Cloud c = makeCloud(3, 2, 5);
    c.layout.fields = {{"x", 0, mesh::kFloat32Field, 1}, {"y", 4, mesh::kFloat32Field, 1}, {"z", 8, mesh::kFloat32Field, 1}};
    c.layout.pointStep = step;
    c.layout.rowStep = step * 3 + 5;
    c.data.assign(static_cast<std::size_t>(c.layout.rowStep) * 2, 0xAB);
    const Eigen::Matrix3Xf p = ramp(6);
    mesh::encodePositions(p, c.layout, c.data.data(), c.data.size());
    Eigen::Matrix3Xf decoded = Eigen::Matrix3Xf::Zero(3, 6);
    const float* storage = decoded.data();
    mesh::decodePositions(c.layout, c.data.data(), c.data.size(), decoded);
    EXPECT_EQ(decoded, p) << "point step " << step;
    EXPECT_EQ(decoded.data(), storage) << "the same size reuses the storage";
    EXPECT_EQ(c.data[c.layout.rowStep - 1], 0xAB) << "padding untouched";
    if (step == 16) {
      EXPECT_EQ(c.data[12], 0xAB) << "the bytes after z untouched";
    }
  }
}

// The motion between two states read from their buffers: the largest distance over the whole cloud (rows with
// padding included) when nothing moved as far as `enough`, else the first distance that did; NaN for a
// non-finite point reached by the scan; a broken layout is named.
TEST(PointCloudLayout, LargestMotionScansUntilAPointHasMovedEnough) {
  Cloud before = makeCloud(3, 2, 5), after = makeCloud(3, 2, 5);
  Eigen::Matrix3Xf p = ramp(6);
  mesh::encodePositions(p, before.layout, before.data.data(), before.data.size());
  p.col(1) += Eigen::Vector3f(0.0f, 0.003f, 0.004f);  // 5 mm
  p.col(4) += Eigen::Vector3f(0.0f, 0.0f, 0.02f);     // 2 cm, in the second row
  mesh::encodePositions(p, after.layout, after.data.data(), after.data.size());
  const auto motion = [&](float enough) {
    return mesh::largestMotion(after.layout, after.data.data(), before.data.data(), after.data.size(), enough);
  };
  EXPECT_NEAR(motion(1.0f), 0.02f, 1e-6f);    // nothing moved 1 m: the largest, from the whole cloud
  EXPECT_NEAR(motion(0.001f), 0.005f, 1e-6f);  // the first point past 1 mm ends the scan
  EXPECT_EQ(mesh::largestMotion(before.layout, before.data.data(), before.data.data(), before.data.size(), 1e-6f), 0.0f);
  p(0, 3) = std::numeric_limits<float>::quiet_NaN();
  mesh::encodePositions(p, after.layout, after.data.data(), after.data.size());
  EXPECT_TRUE(std::isnan(motion(1.0f)));
  EXPECT_NEAR(motion(0.001f), 0.005f, 1e-6f);  // the scan stopped before the NaN
  after.layout.pointStep = 2;
  expectErrorContaining<de::InvalidInputError>([&] { motion(1.0f); }, "lies outside point_step");
}

TEST(PointCloudLayout, EmptyCloudDecodesToNoPoints) {
  const Cloud c = makeCloud(0, 0);
  EXPECT_EQ(mesh::decodePositions(c.layout, c.data.data(), c.data.size()).cols(), 0);
}

TEST(PointCloudLayout, InconsistentLayoutsAreNamed) {
  Cloud c = makeCloud(2, 2);
  c.layout.fields.erase(c.layout.fields.begin() + 2);
  expectInvalid(c, "no 'y' field");
  c = makeCloud(2, 2);
  c.layout.fields[3].datatype = 8;  // float64
  expectInvalid(c, "'z' is not a single float32");
  c = makeCloud(2, 2);
  c.layout.fields[0].count = 2;
  expectInvalid(c, "'x' is not a single float32");
  c = makeCloud(2, 2);
  c.layout.fields[3].offset = 13;
  expectInvalid(c, "'z' lies outside point_step");
  c = makeCloud(2, 2);
  c.layout.fields[0].offset = 0xFFFFFFFFu;  // offset + 4 must not wrap around
  expectInvalid(c, "'x' lies outside point_step");
  c = makeCloud(2, 2);
  c.layout.isBigEndian = true;
  expectInvalid(c, "big-endian");
  c = makeCloud(2, 2);
  c.data.pop_back();
  expectInvalid(c, "does not match");
  c = makeCloud(2, 2);
  c.layout.rowStep = 16;  // two 16-byte points do not fit a 16-byte row
  c.data.resize(32);
  expectInvalid(c, "does not match");
  c = makeCloud(2, 1);
  c.layout.width = 0xFFFFFFFFu;  // a lying width must not be trusted against the buffer
  expectInvalid(c, "does not match");
}

TEST(TriangleMeshFromCloud, FanTriangulatesPolygonsAndNamesBadOnes) {
  Cloud c = makeCloud(4, 1);
  mesh::encodePositions(ramp(4), c.layout, c.data.data(), c.data.size());
  const auto corners = [](const std::vector<std::uint32_t>& polygon) -> const auto& { return polygon; };
  const std::vector<std::vector<std::uint32_t>> quad = {{0, 1, 2, 3}, {1, 2}};
  const mesh::TriangleMesh m = mesh::triangleMeshFromCloud(c.layout, c.data.data(), c.data.size(), quad, corners);
  EXPECT_EQ(m.vertices, ramp(4).cast<double>());
  ASSERT_EQ(m.numTriangles(), 2);  // the line is skipped
  EXPECT_EQ(m.triangles.col(1), Eigen::Vector3i(0, 2, 3));
  const auto message = [&](const Cloud& cloud, const std::vector<std::vector<std::uint32_t>>& polygons) {
    try {
      mesh::triangleMeshFromCloud(cloud.layout, cloud.data.data(), cloud.data.size(), polygons, corners);
    } catch (const de::InvalidInputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(message(c, {{0, 1}}), "mesh has no triangles");
  EXPECT_EQ(message(c, {{0, 1, 4}}), "polygon 0 references vertex 4 of 4");
  EXPECT_EQ(message(makeCloud(0, 1), quad), "mesh has no vertices");
}

TEST(PointCloudLayout, NoPointsMeansNoWorkWhateverTheHeightSays) {
  // fuzz_point_cloud: width 0 and height ~4e9 (an empty buffer matches) made both loops turn 4e9 times.
  mesh::PointCloudLayout layout = makeCloud(1, 1).layout;
  layout.width = 0;
  layout.height = 0xFFFFFFFFu;
  layout.rowStep = 0;
  const std::uint8_t none = 0;
  const auto start = std::chrono::steady_clock::now();
  EXPECT_EQ(mesh::decodePositions(layout, &none, 0).cols(), 0);
  mesh::encodePositions(Eigen::Matrix3Xf(3, 0), layout, nullptr, 0);
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 0.5);
}
