#include "deformation_enrichment/enrichment/example_set_reduction.hpp"

#include <string>

#include "deformation_enrichment/enrichment/descriptor_order.hpp"
#include "deformation_enrichment/enrichment/stamp.hpp"
#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::enrichment {

examples::ExampleSet withStampResolution(const examples::ExampleSet& set, int resolution) {
  if (resolution < 2) throw InvalidInputError("withStampResolution: needs at least 2 nodes per side");
  examples::ExampleSet reduced = set;
  Eigen::Matrix2Xd nodes(2, resolution * resolution);
  Eigen::Matrix3Xd values;
  for (examples::Example& e : reduced.examples) {
    examples::validateExample(e, "withStampResolution");
    const double R = e.stampRadius, spacing = 2.0 * R / (resolution - 1);
    for (int row = 0; row < resolution; ++row)
      for (int col = 0; col < resolution; ++col)
        nodes.col(row * resolution + col) = Eigen::Vector2d(-R + col * spacing, -R + row * spacing);
    lookUpStamp(e.stamp, R, nodes, values);
    cv::Mat stamp(resolution, resolution, CV_32FC3);
    for (int row = 0; row < resolution; ++row)
      for (int col = 0; col < resolution; ++col) {
        const Eigen::Vector3d v = values.col(row * resolution + col);
        stamp.at<cv::Vec3f>(row, col) = cv::Vec3f(static_cast<float>(v.x()), static_cast<float>(v.y()), static_cast<float>(v.z()));
      }
    e.stamp = stamp;
  }
  return reduced;
}

examples::ExampleSet withHermiteOrders(const examples::ExampleSet& set, int siteOrder, int deformationOrder) {
  examples::ExampleSet reduced = set;
  for (examples::Example& e : reduced.examples) {
    e.rho = truncatedMoments(e.rho, siteOrder);
    e.mu = truncatedMoments(e.mu, deformationOrder);
  }
  return reduced;
}

}  // namespace deformation_enrichment::enrichment
