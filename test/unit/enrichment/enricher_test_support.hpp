#pragma once
// The small slab surface, enricher options, dents, stamps and one-example sets the enrichment unit tests share.
#include <opencv2/core.hpp>

#include <cmath>

#include "deformation_enrichment/enrichment/contact_enricher.hpp"
#include "deformation_enrichment/mesh/grid_tet_mesh.hpp"
#include "deformation_enrichment/mesh/tet_surface.hpp"

namespace de_test {

// 10 x 10 x 2 cm, 16 x 16 x 3 cells (6.25 mm on top).
inline deformation_enrichment::mesh::TriangleMesh slabSurface() {
  namespace mesh = deformation_enrichment::mesh;
  return mesh::extractSurface(mesh::gridTetMesh(Eigen::Vector3d(-0.05, -0.05, 0.0), Eigen::Vector3d(0.05, 0.05, 0.02),
                                                Eigen::Vector3i(16, 16, 3)))
      .surface;
}

// h = 8 mm, R = 2 cm, interior samples every 3 mm.
inline deformation_enrichment::enrichment::ContactEnricherOptions enricherOptions() {
  deformation_enrichment::enrichment::ContactEnricherOptions o;
  o.descriptors.window.scale = 0.008;
  o.stampRadius = 0.02;
  o.sampleSpacing = 0.003;
  return o;
}

// A dent with a lateral shear around `centre` (sign flips it): smooth, so MLS sees a clear deformation.
inline Eigen::Matrix3Xd dented(const Eigen::Matrix3Xd& rest, const Eigen::Vector3d& centre, double sign) {
  Eigen::Matrix3Xd current = rest;
  for (Eigen::Index v = 0; v < rest.cols(); ++v) {
    const double g = std::exp(-(rest.col(v) - centre).squaredNorm() / (2.0 * 0.008 * 0.008));
    current.col(v) += sign * g * Eigen::Vector3d(0.002, 0.0005, -0.003);
  }
  return current;
}

inline cv::Mat syntheticStamp(int n, double radius) {
  cv::Mat stamp(n, n, CV_32FC3);
  for (int j = 0; j < n; ++j)
    for (int k = 0; k < n; ++k) {
      const double phi = -radius + 2.0 * radius * k / (n - 1), varphi = -radius + 2.0 * radius * j / (n - 1);
      stamp.at<cv::Vec3f>(j, k) = cv::Vec3f(static_cast<float>(2e-4 * std::cos(300.0 * varphi)), 0.0f,
                                            static_cast<float>(1e-3 * std::sin(250.0 * phi) * std::cos(150.0 * varphi)));
    }
  return stamp;
}

inline deformation_enrichment::examples::ExampleSet oneExampleSet(const deformation_enrichment::enrichment::ContactDescription& d, const cv::Mat& stamp, double radius) {
  deformation_enrichment::examples::Example e;
  e.contact = d.p;
  e.frame = d.B;
  e.rho = d.rho;
  e.mu = d.mu;
  e.stamp = stamp;
  e.stampRadius = radius;
  e.sceneId = "synthetic";
  deformation_enrichment::examples::ExampleSet set;
  set.metadata.scene = "synthetic";
  set.examples.push_back(e);
  return set;
}

}  // namespace de_test
