#include "deformation_enrichment/enrichment/stamp.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::enrichment {

namespace {

void checkFrame(const Eigen::Vector3d& p, const Eigen::Matrix3d& B, const char* what) {
  if (!p.allFinite() || !B.allFinite()) throw InvalidInputError(std::string(what) + ": contact or frame is not finite");
  if ((B.transpose() * B - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-6)
    throw InvalidInputError(std::string(what) + ": frame B is not orthonormal");
}

}  // namespace

void checkStamp(const cv::Mat& stamp, double radius, int layers, const char* what) {
  if (stamp.type() != CV_32FC3) throw InvalidInputError(std::string(what) + ": stamp is not CV_32FC3");
  if (stamp.rows < 2 || stamp.cols < 2) throw InvalidInputError(std::string(what) + ": stamp has fewer than 2x2 nodes");
  if (layers < 1) throw InvalidInputError(std::string(what) + ": stamp layers must be at least 1");
  if (layers > 1 && stamp.rows != layers * stamp.cols)
    throw InvalidInputError(std::string(what) + ": a stamp of " + std::to_string(layers) + " layers of " + std::to_string(stamp.cols) +
                            "x" + std::to_string(stamp.cols) + " nodes needs " + std::to_string(layers * stamp.cols) + " rows, not " +
                            std::to_string(stamp.rows));
  if (!(std::isfinite(radius) && radius > 0.0)) throw InvalidInputError(std::string(what) + ": stamp radius is not positive and finite");
}

Eigen::Matrix2Xd stampCoordinates(const Eigen::Matrix3Xd& points, const Eigen::Vector3d& p, const Eigen::Matrix3d& B) {
  // Orthogonal projection on the tangent plane of the frame ([Seiler14 §3]): (phi, varphi) = (b_x, b_y)^T (x - p).
  return B.leftCols<2>().transpose() * (points.colwise() - p);
}

cv::Mat rasteriseStamp(const mesh::TriangleMesh& restPatch, const Eigen::Matrix3Xd& frameDisplacement,
                       const Eigen::Vector3d& p, const Eigen::Matrix3d& B, double radius, int resolution) {
  mesh::validate(restPatch, false);
  if (frameDisplacement.cols() != restPatch.vertices.cols())
    throw InvalidInputError("rasteriseStamp: " + std::to_string(frameDisplacement.cols()) + " displacements for " +
                            std::to_string(restPatch.vertices.cols()) + " vertices");
  if (!frameDisplacement.allFinite()) throw InvalidInputError("rasteriseStamp: displacement is not finite");
  checkFrame(p, B, "rasteriseStamp");
  if (!(std::isfinite(radius) && radius > 0.0)) throw InvalidInputError("rasteriseStamp: radius is not positive and finite");
  if (resolution < 2) throw InvalidInputError("rasteriseStamp: resolution must be at least 2");

  const Eigen::Matrix3Xd local = B.transpose() * (restPatch.vertices.colwise() - p);  // (phi, varphi, height)
  const double spacing = 2.0 * radius / (resolution - 1);
  cv::Mat stamp(resolution, resolution, CV_32FC3, cv::Scalar::all(0.0));
  Eigen::ArrayXXd height = Eigen::ArrayXXd::Constant(resolution, resolution, -std::numeric_limits<double>::infinity());

  for (Eigen::Index t = 0; t < restPatch.triangles.cols(); ++t) {
    const Eigen::Vector3i tri = restPatch.triangles.col(t);
    const Eigen::Vector2d a = local.col(tri[0]).head<2>(), b = local.col(tri[1]).head<2>(), c = local.col(tri[2]).head<2>();
    const double area2 = (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
    const double scale = std::max({(b - a).squaredNorm(), (c - a).squaredNorm(), (c - b).squaredNorm()});
    if (std::abs(area2) <= 1e-12 * scale) continue;  // edge-on in this projection: covers no area
    const Eigen::Vector2d lo = a.cwiseMin(b).cwiseMin(c), hi = a.cwiseMax(b).cwiseMax(c);
    const int k0 = std::max(0, static_cast<int>(std::ceil((lo.x() + radius) / spacing - 1e-9)));
    const int k1 = std::min(resolution - 1, static_cast<int>(std::floor((hi.x() + radius) / spacing + 1e-9)));
    const int j0 = std::max(0, static_cast<int>(std::ceil((lo.y() + radius) / spacing - 1e-9)));
    const int j1 = std::min(resolution - 1, static_cast<int>(std::floor((hi.y() + radius) / spacing + 1e-9)));
    const double tolerance = 1e-9;  // nodes on a shared edge belong to either neighbour, never to neither
    for (int j = j0; j <= j1; ++j) {
      for (int k = k0; k <= k1; ++k) {
        const Eigen::Vector2d q(-radius + k * spacing, -radius + j * spacing);
        // Barycentric coordinates of q in the projected triangle (linear interpolation over it).
        const double l1 = ((q - a).x() * (c - a).y() - (q - a).y() * (c - a).x()) / area2;
        const double l2 = ((b - a).x() * (q - a).y() - (b - a).y() * (q - a).x()) / area2;
        const double l0 = 1.0 - l1 - l2;
        if (l0 < -tolerance || l1 < -tolerance || l2 < -tolerance) continue;
        const double h = l0 * local(2, tri[0]) + l1 * local(2, tri[1]) + l2 * local(2, tri[2]);
        if (h <= height(j, k)) continue;
        height(j, k) = h;
        const Eigen::Vector3d d = l0 * frameDisplacement.col(tri[0]) + l1 * frameDisplacement.col(tri[1]) +
                                  l2 * frameDisplacement.col(tri[2]);
        stamp.at<cv::Vec3f>(j, k) = cv::Vec3f(static_cast<float>(d.x()), static_cast<float>(d.y()), static_cast<float>(d.z()));
      }
    }
  }
  return stamp;
}

Eigen::Matrix3Xd volumeStampNodes(const Eigen::Vector3d& p, const Eigen::Matrix3d& B, double radius, int resolution, int layers) {
  checkFrame(p, B, "volumeStampNodes");
  if (!(std::isfinite(radius) && radius > 0.0)) throw InvalidInputError("volumeStampNodes: radius is not positive and finite");
  if (resolution < 2 || layers < 2) throw InvalidInputError("volumeStampNodes: needs at least 2 nodes per side and 2 layers");
  const double spacing = 2.0 * radius / (resolution - 1), height = 2.0 * radius / (layers - 1);
  Eigen::Matrix3Xd nodes(3, static_cast<Eigen::Index>(resolution) * resolution * layers);
  for (int l = 0, i = 0; l < layers; ++l)
    for (int j = 0; j < resolution; ++j)
      for (int k = 0; k < resolution; ++k, ++i)
        nodes.col(i) = p + B * Eigen::Vector3d(-radius + k * spacing, -radius + j * spacing, -radius + l * height);
  return nodes;
}

cv::Mat volumeStampFromNodes(const Eigen::Matrix3Xd& values, const std::vector<char>& known, int resolution, int layers) {
  const Eigen::Index count = static_cast<Eigen::Index>(resolution) * resolution * layers;
  if (resolution < 2 || layers < 2) throw InvalidInputError("volumeStampFromNodes: needs at least 2 nodes per side and 2 layers");
  if (values.cols() != count || static_cast<Eigen::Index>(known.size()) != count)
    throw InvalidInputError("volumeStampFromNodes: " + std::to_string(values.cols()) + " values and " + std::to_string(known.size()) +
                            " flags for " + std::to_string(count) + " nodes");
  Eigen::Matrix3Xd filled = values;
  std::vector<char> done(known);
  std::vector<Eigen::Index> front;
  for (Eigen::Index i = 0; i < count; ++i) {
    if (!done[static_cast<std::size_t>(i)]) continue;
    if (!values.col(i).allFinite()) throw InvalidInputError("volumeStampFromNodes: a known value is not finite");
    front.push_back(i);
  }
  if (front.empty()) throw InvalidInputError("volumeStampFromNodes: no node lies in the object");
  // Breadth-first over the 6-neighbour grid: each wave of unknown nodes takes the mean of its known neighbours.
  const Eigen::Index layer = static_cast<Eigen::Index>(resolution) * resolution;
  const auto neighbours = [&](Eigen::Index i, auto&& visit) {
    const Eigen::Index k = i % resolution, j = (i / resolution) % resolution, l = i / layer;
    if (k > 0) visit(i - 1);
    if (k + 1 < resolution) visit(i + 1);
    if (j > 0) visit(i - resolution);
    if (j + 1 < resolution) visit(i + resolution);
    if (l > 0) visit(i - layer);
    if (l + 1 < layers) visit(i + layer);
  };
  while (!front.empty()) {
    std::vector<Eigen::Index> wave;
    for (const Eigen::Index i : front)
      neighbours(i, [&](Eigen::Index n) {
        if (!done[static_cast<std::size_t>(n)] && (wave.empty() || wave.back() != n)) wave.push_back(n);
      });
    std::sort(wave.begin(), wave.end());
    wave.erase(std::unique(wave.begin(), wave.end()), wave.end());
    for (const Eigen::Index i : wave) {
      Eigen::Vector3d sum = Eigen::Vector3d::Zero();
      int n = 0;
      neighbours(i, [&](Eigen::Index m) {
        if (done[static_cast<std::size_t>(m)] == 1) sum += filled.col(m), ++n;
      });
      filled.col(i) = sum / n;
    }
    for (const Eigen::Index i : wave) done[static_cast<std::size_t>(i)] = 1;  // known for the next wave only
    front = std::move(wave);
  }
  cv::Mat stamp(layers * resolution, resolution, CV_32FC3);
  for (Eigen::Index i = 0; i < count; ++i)
    stamp.at<cv::Vec3f>(static_cast<int>(i / resolution), static_cast<int>(i % resolution)) =
        cv::Vec3f(static_cast<float>(filled(0, i)), static_cast<float>(filled(1, i)), static_cast<float>(filled(2, i)));
  return stamp;
}

void lookUpStamp(const cv::Mat& stamp, double radius, const Eigen::Matrix2Xd& coordinates, Eigen::Matrix3Xd& out) {
  checkStamp(stamp, radius, 1, "lookUpStamp");
  if (!coordinates.allFinite()) throw InvalidInputError("lookUpStamp: coordinates are not finite");
  // Own bilinear interpolation rather than cv::remap: remap quantises INTER_LINEAR weights to 1/32 of a
  // cell and limits sizes to SHRT_MAX, which would break float-precision reproduction of smooth fields.
  out.resize(3, coordinates.cols());
  for (Eigen::Index i = 0; i < coordinates.cols(); ++i) out.col(i) = sampleStamp(stamp, radius, coordinates(0, i), coordinates(1, i));
}

cv::Mat rasteriseFacingPatch(const mesh::TriangleMesh& surface, const Eigen::Matrix3Xd& displacement, const Eigen::Vector3d& p,
                             const Eigen::Matrix3d& toFrame, const Eigen::Matrix3d& B, double radius, int resolution,
                             double edge) {
  if (displacement.cols() != surface.vertices.cols())
    throw InvalidInputError("rasteriseFacingPatch: one displacement per surface vertex expected");
  std::vector<int> toPatch(static_cast<std::size_t>(surface.vertices.cols()), -1);
  std::vector<int> patchVertices;
  std::vector<Eigen::Vector3i> patchTriangles;
  const double reach = std::sqrt(2.0) * radius + 2.0 * edge;
  for (Eigen::Index f = 0; f < surface.triangles.cols(); ++f) {
    const Eigen::Vector3i t = surface.triangles.col(f);
    const Eigen::Vector3d a = surface.vertices.col(t(0)), b = surface.vertices.col(t(1)), c = surface.vertices.col(t(2));
    if ((b - a).cross(c - a).dot(B.col(2)) <= 0.0) continue;
    if ((a - p).norm() > reach || (b - p).norm() > reach || (c - p).norm() > reach) continue;
    Eigen::Vector3i local;
    for (int k = 0; k < 3; ++k) {
      int& id = toPatch[static_cast<std::size_t>(t(k))];
      if (id < 0) {
        id = static_cast<int>(patchVertices.size());
        patchVertices.push_back(t(k));
      }
      local(k) = id;
    }
    patchTriangles.push_back(local);
  }
  if (patchTriangles.empty()) throw InvalidInputError("rasteriseFacingPatch: no surface facing the contact's normal near it");
  mesh::TriangleMesh patch;
  patch.vertices.resize(3, static_cast<Eigen::Index>(patchVertices.size()));
  patch.triangles.resize(3, static_cast<Eigen::Index>(patchTriangles.size()));
  Eigen::Matrix3Xd frameDisplacement(3, patch.vertices.cols());
  for (std::size_t i = 0; i < patchVertices.size(); ++i) {
    patch.vertices.col(static_cast<Eigen::Index>(i)) = surface.vertices.col(patchVertices[i]);
    frameDisplacement.col(static_cast<Eigen::Index>(i)) = toFrame * displacement.col(patchVertices[i]);
  }
  for (std::size_t f = 0; f < patchTriangles.size(); ++f) patch.triangles.col(static_cast<Eigen::Index>(f)) = patchTriangles[f];
  return rasteriseStamp(patch, frameDisplacement, p, B, radius, resolution);
}

}  // namespace deformation_enrichment::enrichment
