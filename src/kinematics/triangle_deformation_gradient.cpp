#include "deformation_enrichment/kinematics/triangle_deformation_gradient.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <Eigen/LU>

#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::kinematics {
namespace {

// Area below this fraction of the longest squared edge counts as degenerate (relative, so scale-free).
constexpr double kDegenerateAreaRatio = 1e-12;

bool isDegenerate(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const double longest2 = std::max({a.squaredNorm(), b.squaredNorm(), (b - a).squaredNorm()});
  return !(longest2 > 0.0) || !(0.5 * c.norm() > kDegenerateAreaRatio * longest2);
}

// Deterministic frame for a collapsed deformed triangle: e1 along its longest edge (x-axis if it shrank
// to a point), e2 any unit vector perpendicular to e1. All deformed edges lie along e1, so projecting
// onto this frame loses no length and C = FᵀF stays exact.
TriangleFrame fallbackFrame(const Eigen::Vector3d& u1, const Eigen::Vector3d& u2) {
  const Eigen::Vector3d candidates[3] = {u1, u2, u2 - u1};
  const Eigen::Vector3d* longest = &candidates[0];
  for (const auto& c : candidates) {
    if (c.squaredNorm() > longest->squaredNorm()) longest = &c;
  }
  TriangleFrame frame;
  const Eigen::Vector3d e1 = longest->squaredNorm() > 0.0 ? longest->normalized() : Eigen::Vector3d::UnitX();
  const Eigen::Vector3d e2 = e1.unitOrthogonal();
  frame.axes << e1, e2;
  frame.normal = e1.cross(e2);
  return frame;
}

}  // namespace

TriangleFrame triangleFrame(const Eigen::Vector3d& v0, const Eigen::Vector3d& v1, const Eigen::Vector3d& v2) {
  if (!v0.allFinite() || !v1.allFinite() || !v2.allFinite()) {
    throw InvalidInputError("triangleFrame: vertex has a NaN or infinite coordinate");
  }
  const Eigen::Vector3d a = v1 - v0, b = v2 - v0, n = a.cross(b);
  if (isDegenerate(a, b, n)) throw InvalidInputError("triangleFrame: degenerate (zero-area) triangle");
  TriangleFrame frame;
  frame.normal = n.normalized();
  const Eigen::Vector3d e1 = a.normalized();
  frame.axes << e1, frame.normal.cross(e1);
  return frame;
}

TriangleStrain triangleDeformationGradient(const Eigen::Vector3d& X0, const Eigen::Vector3d& X1,
                                           const Eigen::Vector3d& X2, const Eigen::Vector3d& x0,
                                           const Eigen::Vector3d& x1, const Eigen::Vector3d& x2) {
  if (!x0.allFinite() || !x1.allFinite() || !x2.allFinite()) {
    throw InvalidInputError("triangleDeformationGradient: deformed vertex has a NaN or infinite coordinate");
  }
  TriangleStrain s;
  s.restFrame = triangleFrame(X0, X1, X2);  // throws for a degenerate rest triangle
  const Eigen::Vector3d u1 = x1 - x0, u2 = x2 - x0;
  s.deformedFrame = isDegenerate(u1, u2, u1.cross(u2)) ? fallbackFrame(u1, u2) : triangleFrame(x0, x1, x2);

  // Edge matrices in each triangle's own 2D frame.
  Eigen::Matrix2d restEdges, deformedEdges;
  restEdges << s.restFrame.axes.transpose() * (X1 - X0), s.restFrame.axes.transpose() * (X2 - X0);
  deformedEdges << s.deformedFrame.axes.transpose() * u1, s.deformedFrame.axes.transpose() * u2;
  s.F = deformedEdges * restEdges.inverse();  // [Yan19 eq. 2]: F = [u1 u2][ū1 ū2]^-1

  // C = FᵀF = U² ([Yan19 eqs. 15-18]); U = sum lambda_i v_i v_iᵀ with lambda_i² the eigenvalues of C (eq. 20).
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(s.F.transpose() * s.F);
  const Eigen::Vector2d lambda2 = eig.eigenvalues().cwiseMax(0.0);  // ascending; clamp round-off
  s.principalStretches << std::sqrt(lambda2[1]), std::sqrt(lambda2[0]);
  s.principalDirections << eig.eigenvectors().col(1), eig.eigenvectors().col(0);
  s.U = s.principalDirections * s.principalStretches.asDiagonal() * s.principalDirections.transpose();
  return s;
}

Eigen::Matrix2Xd principalStretches(const mesh::TriangleMesh& rest, const mesh::TriangleMesh& deformed) {
  mesh::validate(rest, true);
  if (deformed.numVertices() != rest.numVertices()) {
    throw InvalidInputError("principalStretches: deformed mesh has " + std::to_string(deformed.numVertices()) +
                            " vertices, rest mesh " + std::to_string(rest.numVertices()));
  }
  if (deformed.triangles.cols() != rest.triangles.cols() || deformed.triangles != rest.triangles) {
    throw InvalidInputError("principalStretches: deformed and rest mesh have different triangles");
  }
  if (!deformed.vertices.allFinite()) {
    throw InvalidInputError("principalStretches: deformed mesh has a NaN or infinite vertex");
  }
  Eigen::Matrix2Xd stretches(2, rest.numTriangles());
  for (Eigen::Index t = 0; t < rest.numTriangles(); ++t) {
    const Eigen::Vector3i tri = rest.triangles.col(t);
    try {
      stretches.col(t) = triangleDeformationGradient(rest.vertices.col(tri[0]), rest.vertices.col(tri[1]),
                                                     rest.vertices.col(tri[2]), deformed.vertices.col(tri[0]),
                                                     deformed.vertices.col(tri[1]), deformed.vertices.col(tri[2]))
                             .principalStretches;
    } catch (const InvalidInputError& e) {
      throw InvalidInputError("principalStretches: triangle " + std::to_string(t) + ": " + e.what());
    }
  }
  return stretches;
}

}  // namespace deformation_enrichment::kinematics
