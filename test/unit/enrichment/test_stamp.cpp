// Stamp rasterisation and look-up: affine fields are reproduced, outside is zero, resolution converges.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <functional>
#include <random>

#include "deformation_enrichment/enrichment/stamp.hpp"
#include "deformation_enrichment/error.hpp"

namespace de = deformation_enrichment;
namespace en = deformation_enrichment::enrichment;

namespace {

struct Patch {
  de::mesh::TriangleMesh mesh;
  Eigen::Matrix2Xd local;  // (phi, varphi) of each vertex
};

// A regular grid patch over [lo, hi]^2 in stamp coordinates, lifted by `height` along b_z and placed at
// p with frame B; interior vertices jittered so triangles are irregular.
Patch gridPatch(int n, double lo, double hi, const Eigen::Vector3d& p, const Eigen::Matrix3d& B,
                const std::function<double(double, double)>& height, unsigned seed = 3) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(-0.3, 0.3);
  const double h = (hi - lo) / (n - 1);
  Patch patch;
  patch.mesh.vertices.resize(3, n * n);
  patch.local.resize(2, n * n);
  for (int j = 0; j < n; ++j)
    for (int k = 0; k < n; ++k) {
      const bool interior = j > 0 && k > 0 && j < n - 1 && k < n - 1;
      const double x = lo + k * h + (interior ? jitter(rng) * h : 0.0);
      const double y = lo + j * h + (interior ? jitter(rng) * h : 0.0);
      patch.local.col(j * n + k) = Eigen::Vector2d(x, y);
      patch.mesh.vertices.col(j * n + k) = p + B * Eigen::Vector3d(x, y, height(x, y));
    }
  patch.mesh.triangles.resize(3, 2 * (n - 1) * (n - 1));
  int t = 0;
  for (int j = 0; j + 1 < n; ++j)
    for (int k = 0; k + 1 < n; ++k) {
      const int v = j * n + k;
      patch.mesh.triangles.col(t++) = Eigen::Vector3i(v, v + 1, v + n + 1);
      patch.mesh.triangles.col(t++) = Eigen::Vector3i(v, v + n + 1, v + n);
    }
  return patch;
}

Eigen::Matrix3d someFrame() { return Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, -2, 0.5).normalized()).toRotationMatrix(); }

Eigen::Matrix2Xd randomPoints(int n, double extent, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-extent, extent);
  Eigen::Matrix2Xd q(2, n);
  for (int i = 0; i < n; ++i) q.col(i) = Eigen::Vector2d(u(rng), u(rng));
  return q;
}

}  // namespace

TEST(Stamp, AffineFieldIsReproducedAtArbitraryPoints) {
  const double R = 0.015;
  const Eigen::Vector3d p(0.01, -0.02, 0.03);
  const Eigen::Matrix3d B = someFrame();
  // Curved patch: the height does not enter the projection, only the z-buffer.
  const Patch patch = gridPatch(23, -1.3 * R, 1.3 * R, p, B, [](double x, double y) { return 3.0 * x * x - y * y; });
  Eigen::Matrix<double, 3, 2> A;
  A << 0.05, -0.02, 0.01, 0.08, -0.03, 0.04;
  const Eigen::Vector3d c(1e-3, -2e-3, 5e-4);
  const Eigen::Matrix3Xd d = (A * patch.local).colwise() + c;
  const cv::Mat stamp = en::rasteriseStamp(patch.mesh, d, p, B, R, 64);
  ASSERT_EQ(stamp.rows, 64);
  ASSERT_EQ(stamp.type(), CV_32FC3);

  const Eigen::Matrix2Xd q = randomPoints(2000, R, 11);
  Eigen::Matrix3Xd out;
  en::lookUpStamp(stamp, R, q, out);
  const Eigen::Matrix3Xd expected = (A * q).colwise() + c;
  const double scale = expected.cwiseAbs().maxCoeff();
  EXPECT_LT((out - expected).cwiseAbs().maxCoeff(), 4.0 * scale * 1.2e-7);  // float storage precision
  // Corners and edges of the square are inside too.
  Eigen::Matrix2Xd corners(2, 4);
  corners << -R, R, R, -R, -R, -R, R, R;
  en::lookUpStamp(stamp, R, corners, out);
  EXPECT_LT((out - ((A * corners).colwise() + c)).cwiseAbs().maxCoeff(), 4.0 * scale * 1.2e-7);
}

TEST(Stamp, StampCoordinatesProjectOnTheFrame) {
  const Eigen::Vector3d p(0.1, 0.2, 0.3);
  const Eigen::Matrix3d B = someFrame();
  Eigen::Matrix3Xd x(3, 1);
  x.col(0) = p + 0.2 * B.col(0) - 0.5 * B.col(1) + 7.0 * B.col(2);
  const Eigen::Matrix2Xd q = en::stampCoordinates(x, p, B);
  EXPECT_NEAR(q(0, 0), 0.2, 1e-14);
  EXPECT_NEAR(q(1, 0), -0.5, 1e-14);
}

TEST(Stamp, LookUpOutsideTheSquareIsZero) {
  const double R = 0.01;
  cv::Mat stamp(16, 16, CV_32FC3, cv::Scalar(1.0, 2.0, 3.0));
  Eigen::Matrix2Xd q(2, 6);
  q << 1.0001 * R, -1.0001 * R, 0.0, 0.0, 5 * R, -3 * R, 0.0, 0.0, 1.0001 * R, -1.0001 * R, 5 * R, 0.2 * R;
  Eigen::Matrix3Xd out;
  en::lookUpStamp(stamp, R, q, out);
  EXPECT_EQ(out.cwiseAbs().maxCoeff(), 0.0);
  q.resize(2, 1);
  q << R, -R;  // exactly on the corner: inside
  en::lookUpStamp(stamp, R, q, out);
  EXPECT_NEAR(out(2, 0), 3.0, 1e-6);
}

TEST(Stamp, UncoveredNodesAreZeroAndTheOutsideSideWins) {
  const double R = 0.01;
  const Eigen::Vector3d p = Eigen::Vector3d::Zero();
  const Eigen::Matrix3d B = Eigen::Matrix3d::Identity();
  // Top sheet covering only phi in [0, 1.2R], a bottom sheet below it covering everything.
  const Patch top = gridPatch(9, 0.0, 1.2 * R, p, B, [](double, double) { return 0.0; });
  Patch half = top;
  for (Eigen::Index i = 0; i < half.mesh.vertices.cols(); ++i) {
    half.mesh.vertices(1, i) = -1.2 * R + (half.local(1, i) / (1.2 * R)) * 2.4 * R;  // stretch varphi over the square
    half.local(1, i) = half.mesh.vertices(1, i);
  }
  Eigen::Matrix3Xd up = Eigen::Matrix3Xd::Zero(3, half.mesh.vertices.cols());
  up.row(2).setConstant(1.0);
  cv::Mat stamp = en::rasteriseStamp(half.mesh, up, p, B, R, 33);
  for (int j = 0; j < 33; ++j)
    for (int k = 0; k < 33; ++k) EXPECT_EQ(stamp.at<cv::Vec3f>(j, k)[2], k >= 16 ? 1.0f : 0.0f) << j << "," << k;

  // Two-sided patch: the lower sheet (height -0.005) carries -1, the upper one +1: the upper one wins.
  const Patch lower = gridPatch(9, -1.2 * R, 1.2 * R, p, B, [](double, double) { return -0.005; });
  const Patch upper = gridPatch(7, -1.2 * R, 1.2 * R, p, B, [](double, double) { return 0.0; }, 5);
  de::mesh::TriangleMesh both;
  both.vertices.resize(3, lower.mesh.vertices.cols() + upper.mesh.vertices.cols());
  both.vertices << lower.mesh.vertices, upper.mesh.vertices;
  both.triangles.resize(3, lower.mesh.triangles.cols() + upper.mesh.triangles.cols());
  both.triangles << lower.mesh.triangles, (upper.mesh.triangles.array() + static_cast<int>(lower.mesh.vertices.cols())).matrix();
  Eigen::Matrix3Xd d = Eigen::Matrix3Xd::Zero(3, both.vertices.cols());
  d.row(2).head(lower.mesh.vertices.cols()).setConstant(-1.0);
  d.row(2).tail(upper.mesh.vertices.cols()).setConstant(1.0);
  stamp = en::rasteriseStamp(both, d, p, B, R, 17);
  double minValue = 0, maxValue = 0;
  std::vector<cv::Mat> channels;
  cv::split(stamp, channels);
  cv::minMaxLoc(channels[2], &minValue, &maxValue);
  EXPECT_EQ(minValue, 1.0);
  EXPECT_EQ(maxValue, 1.0);
}

TEST(Stamp, ResolutionChangesConverge) {
  const double R = 0.02;
  const Eigen::Vector3d p(0.0, 0.0, 0.02);
  const Eigen::Matrix3d B = someFrame();
  const auto field = [R](double x, double y) -> Eigen::Vector3d {
    return Eigen::Vector3d(std::sin(3.0 * x / R), std::cos(2.0 * y / R) * x / R, std::exp(-(x * x + y * y) / (R * R))) * 1e-3;
  };
  const Patch patch = gridPatch(301, -1.1 * R, 1.1 * R, p, B, [](double, double) { return 0.0; });
  Eigen::Matrix3Xd d(3, patch.local.cols());
  for (Eigen::Index i = 0; i < d.cols(); ++i) d.col(i) = field(patch.local(0, i), patch.local(1, i));
  const Eigen::Matrix2Xd q = randomPoints(3000, R, 17);
  Eigen::Matrix3Xd expected(3, q.cols());
  for (Eigen::Index i = 0; i < q.cols(); ++i) expected.col(i) = field(q(0, i), q(1, i));
  double previous = 0.0;
  for (int resolution : {9, 17, 33}) {
    Eigen::Matrix3Xd out;
    en::lookUpStamp(en::rasteriseStamp(patch.mesh, d, p, B, R, resolution), R, q, out);
    const double error = std::sqrt((out - expected).squaredNorm() / q.cols());
    if (previous > 0.0) {
      EXPECT_LT(error, previous / 3.0) << "resolution " << resolution;  // O(h^2): ~4x per halving
    }
    previous = error;
  }
  EXPECT_LT(previous, 2e-5);
}

TEST(Stamp, BadInputThrows) {
  const Eigen::Vector3d p = Eigen::Vector3d::Zero();
  const Eigen::Matrix3d B = Eigen::Matrix3d::Identity();
  const Patch patch = gridPatch(4, -1.0, 1.0, p, B, [](double, double) { return 0.0; });
  const Eigen::Matrix3Xd d = Eigen::Matrix3Xd::Zero(3, patch.mesh.vertices.cols());
  EXPECT_THROW(en::rasteriseStamp(patch.mesh, d.leftCols(3), p, B, 1.0), de::InvalidInputError);
  EXPECT_THROW(en::rasteriseStamp(patch.mesh, d, p, 2.0 * B, 1.0), de::InvalidInputError);
  EXPECT_THROW(en::rasteriseStamp(patch.mesh, d, p, B, 0.0), de::InvalidInputError);
  EXPECT_THROW(en::rasteriseStamp(patch.mesh, d, p, B, 1.0, 1), de::InvalidInputError);
  Eigen::Matrix3Xd nan = d;
  nan(1, 2) = std::nan("");
  EXPECT_THROW(en::rasteriseStamp(patch.mesh, nan, p, B, 1.0), de::InvalidInputError);
  de::mesh::TriangleMesh empty;
  EXPECT_THROW(en::rasteriseStamp(empty, Eigen::Matrix3Xd(3, 0), p, B, 1.0), de::InvalidInputError);
  Eigen::Matrix3Xd out;
  Eigen::Matrix2Xd q = Eigen::Matrix2Xd::Zero(2, 1);
  EXPECT_THROW(en::lookUpStamp(cv::Mat(4, 4, CV_64FC3), 1.0, q, out), de::InvalidInputError);
  EXPECT_THROW(en::lookUpStamp(cv::Mat(4, 4, CV_32FC3), -1.0, q, out), de::InvalidInputError);
  q(0, 0) = std::nan("");
  EXPECT_THROW(en::lookUpStamp(cv::Mat(4, 4, CV_32FC3), 1.0, q, out), de::InvalidInputError);
}

TEST(VolumeStamp, AffineFieldIsReproducedByTrilinearLookUp) {
  const Eigen::Vector3d p(0.01, -0.02, 0.03);
  const Eigen::Matrix3d B = Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  const double R = 0.02;
  const int n = 6, layers = 5;
  const Eigen::Matrix3Xd nodes = en::volumeStampNodes(p, B, R, n, layers);
  ASSERT_EQ(nodes.cols(), n * n * layers);
  Eigen::Matrix3d A;
  A << 0.1, -0.2, 0.3, 0.05, 0.4, -0.1, 0.2, 0.0, -0.3;
  const Eigen::Vector3d c(1e-3, -2e-3, 5e-4);
  const auto field = [&](const Eigen::Vector3d& local) { return Eigen::Vector3d(A * local + c); };
  Eigen::Matrix3Xd values(3, nodes.cols());
  for (Eigen::Index i = 0; i < nodes.cols(); ++i) values.col(i) = field(B.transpose() * (nodes.col(i) - p));
  const cv::Mat stamp = en::volumeStampFromNodes(values, std::vector<char>(static_cast<std::size_t>(nodes.cols()), 1), n, layers);
  ASSERT_EQ(stamp.rows, n * layers);
  ASSERT_EQ(stamp.cols, n);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-R, R);
  for (int k = 0; k < 200; ++k) {
    const Eigen::Vector3d local(u(rng), u(rng), u(rng));
    const Eigen::Vector3d got = en::sampleVolumeStamp(stamp, R, layers, local.x(), local.y(), local.z());
    EXPECT_LT((got - field(local)).norm(), 1e-6) << local.transpose();  // float storage
  }
  EXPECT_EQ(en::sampleVolumeStamp(stamp, R, layers, 0.0, 0.0, 1.01 * R), Eigen::Vector3d::Zero());  // outside the cube
  EXPECT_EQ(en::sampleVolumeStamp(stamp, R, layers, 1.01 * R, 0.0, 0.0), Eigen::Vector3d::Zero());
}

TEST(VolumeStamp, NodesOutsideTheObjectTakeTheNearestKnownValue) {
  // Known below the middle layer only (the object), with a value that depends on the column: the air above
  // takes the top known layer's value column by column, so look-up just below the surface is exact.
  const int n = 4, layers = 5;
  Eigen::Matrix3Xd values = Eigen::Matrix3Xd::Zero(3, n * n * layers);
  std::vector<char> known(static_cast<std::size_t>(values.cols()), 0);
  for (int l = 0; l <= 2; ++l)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) {
        const int i = (l * n + j) * n + k;
        values.col(i) = Eigen::Vector3d(k + 10.0 * j, l, 1.0);
        known[static_cast<std::size_t>(i)] = 1;
      }
  const cv::Mat stamp = en::volumeStampFromNodes(values, known, n, layers);
  for (int l = 3; l < layers; ++l)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) {
        const cv::Vec3f v = stamp.at<cv::Vec3f>(l * n + j, k);
        EXPECT_FLOAT_EQ(v[0], static_cast<float>(k + 10.0 * j));
        EXPECT_FLOAT_EQ(v[1], 2.0f);  // the top known layer
      }
  EXPECT_THROW(en::volumeStampFromNodes(values, std::vector<char>(known.size(), 0), n, layers), de::InvalidInputError);
  EXPECT_THROW(en::volumeStampFromNodes(values, std::vector<char>(3, 1), n, layers), de::InvalidInputError);
  Eigen::Matrix3Xd bad = values;
  bad(0, 0) = std::nan("");
  EXPECT_THROW(en::volumeStampFromNodes(bad, known, n, layers), de::InvalidInputError);
  EXPECT_THROW(en::checkStamp(stamp, 0.02, 4, "test"), de::InvalidInputError);  // 5 layers, not 4
  EXPECT_NO_THROW(en::checkStamp(stamp, 0.02, layers, "test"));
}
