// Stamp look-up and rasterisation against independent oracles (SciPy RegularGridInterpolator,
// matplotlib LinearTriInterpolator) run through test/oracle/stamp_oracle.py with /usr/bin/python3.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>

#include "deformation_enrichment/enrichment/stamp.hpp"

namespace en = deformation_enrichment::enrichment;
using nlohmann::json;

namespace {

json runOracle(const json& request, const std::string& name) {
  const std::string in = testing::TempDir() + "stamp_oracle_" + name + "_in.json";
  const std::string out = testing::TempDir() + "stamp_oracle_" + name + "_out.json";
  std::ofstream(in) << request.dump();
  const std::string command = std::string("/usr/bin/python3 ") + DE_SOURCE_DIR + "/test/oracle/stamp_oracle.py " + in + " " + out;
  const int status = std::system(command.c_str());
  EXPECT_EQ(status, 0) << "oracle failed: " << command;
  std::ifstream answer(out);
  EXPECT_TRUE(answer.good()) << "oracle wrote no answer";
  return status == 0 && answer.good() ? json::parse(answer) : json::object();
}

}  // namespace

TEST(StampOracle, BilinearLookUpMatchesScipy) {
  const double R = 0.012;
  cv::Mat stamp(13, 17, CV_32FC3);  // not square on purpose
  cv::randn(stamp, cv::Scalar::all(0.0), cv::Scalar::all(1.0));
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.2 * R, 1.2 * R);  // some queries outside: zero
  Eigen::Matrix2Xd q(2, 500);
  for (Eigen::Index i = 0; i < q.cols(); ++i) q.col(i) = Eigen::Vector2d(u(rng), u(rng));
  json request;
  request["lookup"] = {{"rows", stamp.rows}, {"cols", stamp.cols}, {"radius", R},
                       {"values", std::vector<float>(stamp.ptr<float>(), stamp.ptr<float>() + stamp.total() * 3)},
                       {"phi", std::vector<double>(q.row(0).begin(), q.row(0).end())},
                       {"varphi", std::vector<double>(q.row(1).begin(), q.row(1).end())}};
  const json answer = runOracle(request, "lookup");
  const std::vector<double> expected = answer.value("lookup", std::vector<double>{});
  ASSERT_EQ(expected.size(), 3u * q.cols());
  Eigen::Matrix3Xd out;
  en::lookUpStamp(stamp, R, q, out);
  for (Eigen::Index i = 0; i < q.cols(); ++i)
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(out(c, i), expected[static_cast<std::size_t>(3 * i + c)], 1e-12) << i;
}

TEST(StampOracle, RasterisationMatchesMatplotlibLinearTriInterpolator) {
  // An irregular single-sheet patch (jittered grid) over part of the square with a non-affine field.
  const double R = 0.01;
  const int n = 15;
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> jitter(-0.3, 0.3);
  const double lo = -0.8 * R, hi = 1.3 * R, h = (hi - lo) / (n - 1);
  deformation_enrichment::mesh::TriangleMesh patch;
  patch.vertices.resize(3, n * n);
  Eigen::Matrix3Xd d(3, n * n);
  for (int j = 0; j < n; ++j)
    for (int k = 0; k < n; ++k) {
      const bool interior = j > 0 && k > 0 && j < n - 1 && k < n - 1;
      const double x = lo + k * h + (interior ? jitter(rng) * h : 0.0), y = lo + j * h + (interior ? jitter(rng) * h : 0.0);
      patch.vertices.col(j * n + k) = Eigen::Vector3d(x, y, 0.1 * x * y / R);
      d.col(j * n + k) = Eigen::Vector3d(std::sin(300 * x), std::cos(200 * y) * x / R, std::exp(-(x * x + y * y) / (R * R)));
    }
  patch.triangles.resize(3, 2 * (n - 1) * (n - 1));
  for (int j = 0, t = 0; j + 1 < n; ++j)
    for (int k = 0; k + 1 < n; ++k) {
      const int v = j * n + k;
      patch.triangles.col(t++) = Eigen::Vector3i(v, v + 1, v + n + 1);
      patch.triangles.col(t++) = Eigen::Vector3i(v, v + n + 1, v + n);
    }
  const int N = 24;
  const cv::Mat stamp = en::rasteriseStamp(patch, d, Eigen::Vector3d::Zero(), Eigen::Matrix3d::Identity(), R, N);

  json request;
  request["raster"] = {{"phi", std::vector<double>(patch.vertices.row(0).begin(), patch.vertices.row(0).end())},
                       {"varphi", std::vector<double>(patch.vertices.row(1).begin(), patch.vertices.row(1).end())},
                       {"triangles", std::vector<int>(patch.triangles.data(), patch.triangles.data() + patch.triangles.size())},
                       {"values", std::vector<double>(d.data(), d.data() + d.size())},
                       {"radius", R},
                       {"resolution", N}};
  const json answer = runOracle(request, "raster");
  const std::vector<double> expected = answer.value("raster", std::vector<double>{});
  ASSERT_EQ(expected.size(), static_cast<std::size_t>(N * N * 3));
  int covered = 0;
  for (int j = 0; j < N; ++j)
    for (int k = 0; k < N; ++k)
      for (int c = 0; c < 3; ++c) {
        const double e = expected[static_cast<std::size_t>((j * N + k) * 3 + c)];
        EXPECT_NEAR(stamp.at<cv::Vec3f>(j, k)[c], e, 2e-6) << j << "," << k << "," << c;  // float storage
        covered += c == 2 && e != 0.0;
      }
  EXPECT_GT(covered, N * N / 2);  // part of the square is covered, part (phi, varphi < -0.8 R) is not
  EXPECT_LT(covered, N * N);
}
