#pragma once
// Root mean square length of a set of 3-vectors (displacements, errors): sqrt(sum |x_i|^2 / n), 0 for none.
#include <Eigen/Core>
#include <cmath>

namespace deformation_enrichment {

inline double rootMeanSquare(const Eigen::Matrix3Xd& vectors) {
  return vectors.cols() > 0 ? std::sqrt(vectors.squaredNorm() / static_cast<double>(vectors.cols())) : 0.0;
}

}  // namespace deformation_enrichment
