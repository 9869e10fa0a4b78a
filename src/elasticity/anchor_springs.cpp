#include "deformation_enrichment/elasticity/anchor_springs.hpp"

#include <cmath>
#include <string>

#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::elasticity {

void AnchorSprings::validate(Eigen::Index vertexCount) const {
  const auto n = static_cast<Eigen::Index>(vertices.size());
  if (stiffness.size() != n || targets.cols() != n)
    throw InvalidInputError("AnchorSprings: " + std::to_string(n) + " vertices but " + std::to_string(stiffness.size()) +
                            " stiffnesses and " + std::to_string(targets.cols()) + " targets");
  if (!targets.allFinite()) throw InvalidInputError("AnchorSprings: targets contain NaN or Inf");
  if (!stiffness.allFinite() || (n > 0 && stiffness.minCoeff() < 0.0))
    throw InvalidInputError("AnchorSprings: stiffness must be finite and non-negative");
  std::vector<char> seen(static_cast<std::size_t>(vertexCount), 0);
  for (int v : vertices) {
    if (v < 0 || v >= vertexCount) throw InvalidInputError("AnchorSprings: vertex " + std::to_string(v) + " out of range");
    if (seen[static_cast<std::size_t>(v)]++) throw InvalidInputError("AnchorSprings: vertex " + std::to_string(v) + " anchored twice");
  }
}

double AnchorSprings::energy(const Eigen::Matrix3Xd& x) const {
  double e = 0.0;
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    const auto c = static_cast<Eigen::Index>(i);
    e += 0.5 * stiffness[c] * (x.col(vertices[i]) - targets.col(c)).squaredNorm();
  }
  return e;
}

void AnchorSprings::addGradient(const Eigen::Matrix3Xd& x, Eigen::VectorXd& g) const {
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    const auto c = static_cast<Eigen::Index>(i);
    g.segment<3>(3 * vertices[i]) += stiffness[c] * (x.col(vertices[i]) - targets.col(c));
  }
}

}  // namespace deformation_enrichment::elasticity
