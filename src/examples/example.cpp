#include "deformation_enrichment/examples/example.hpp"

#include <Eigen/Dense>
#include <cmath>
#include <sstream>

#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::examples {

namespace {
constexpr double kFrameTolerance = 1e-6;

bool finiteMoments(const hermite::MomentList& m) { return m.values().allFinite(); }
}  // namespace

std::string exampleProblem(const Example& example) {
  if (!example.contact.allFinite()) return "contact is not finite";
  if (!example.frame.allFinite()) return "frame is not finite";
  const double orthoError = (example.frame.transpose() * example.frame - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  if (orthoError > kFrameTolerance) {
    std::ostringstream s;
    s << "frame is not orthonormal (max |B^T B - I| = " << orthoError << ")";
    return s.str();
  }
  if (example.frame.determinant() < 0.0) return "frame is not right-handed (det B < 0)";
  if (example.rho.empty()) return "rho is empty";
  if (example.mu.empty()) return "mu is empty";
  if (!finiteMoments(example.rho)) return "rho is not finite";
  if (!finiteMoments(example.mu)) return "mu is not finite";
  if (!(std::isfinite(example.stampRadius) && example.stampRadius > 0.0)) return "stamp radius is not positive and finite";
  if (!std::isfinite(example.pattern.indentDepth) || !example.pattern.drag.allFinite()) return "interaction pattern is not finite";
  if (example.stamp.type() != CV_32FC3) return "stamp is not CV_32FC3";
  if (example.stamp.rows < 2 || example.stamp.cols < 2) return "stamp has fewer than 2x2 nodes";
  if (example.stampLayers < 1) return "stamp layers must be at least 1";
  if (example.stampLayers > 1 && example.stamp.rows != example.stampLayers * example.stamp.cols)
    return "a volume stamp's rows must be its layers times its columns";
  if (!cv::checkRange(example.stamp, true)) return "stamp contains NaN or Inf";
  return {};
}

void validateExample(const Example& example, const std::string& what) {
  const std::string problem = exampleProblem(example);
  if (!problem.empty()) throw InvalidInputError(what + ": " + problem);
}

}  // namespace deformation_enrichment::examples
