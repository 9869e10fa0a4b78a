#include "deformation_enrichment/kinematics/tet_deformation_gradient.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include <Eigen/LU>

#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::kinematics {
namespace {

// Edge matrix [v1-v0, v2-v0, v3-v0].
Eigen::Matrix3d edgeMatrix(const Matrix34d& v) { return v.rightCols<3>().colwise() - v.col(0); }

}  // namespace

Eigen::Matrix3d restShapeInverse(const Matrix34d& rest) {
  if (!rest.allFinite()) throw InvalidInputError("tet rest vertex has a NaN or infinite coordinate");
  const Eigen::Matrix3d Dm = edgeMatrix(rest);
  double longest2 = 0.0;  // longest squared edge over all six edges
  for (int i = 0; i < 4; ++i) {
    for (int j = i + 1; j < 4; ++j) longest2 = std::max(longest2, (rest.col(j) - rest.col(i)).squaredNorm());
  }
  const double volume6 = Dm.determinant();
  if (!(longest2 > 0.0) || !(std::abs(volume6) > 6e-12 * longest2 * std::sqrt(longest2))) {
    throw InvalidInputError("degenerate (zero-volume) rest tet");
  }
  return Dm.inverse();
}

Eigen::Matrix3d tetDeformationGradient(const Matrix34d& rest, const Matrix34d& deformed) {
  const Eigen::Matrix3d DmInv = restShapeInverse(rest);
  if (!deformed.allFinite()) throw InvalidInputError("tet deformed vertex has a NaN or infinite coordinate");
  return edgeMatrix(deformed) * DmInv;  // F = Ds Dm^-1
}

Matrix3dList restShapeInverses(const mesh::TetMesh& rest) {
  mesh::validate(rest, false);  // orientation is irrelevant here; degeneracy is checked below
  Matrix3dList inverses(static_cast<size_t>(rest.numTets()));
  for (Eigen::Index t = 0; t < rest.numTets(); ++t) {
    Matrix34d corners;
    for (int k = 0; k < 4; ++k) corners.col(k) = rest.vertices.col(rest.tets(k, t));
    try {
      inverses[static_cast<size_t>(t)] = restShapeInverse(corners);
    } catch (const InvalidInputError& e) {
      throw InvalidInputError("tet " + std::to_string(t) + ": " + e.what());
    }
  }
  return inverses;
}

Matrix3dList tetDeformationGradients(const mesh::TetMesh& rest, const Matrix3dList& restInverses,
                                     const Eigen::Matrix3Xd& deformedVertices) {
  if (static_cast<Eigen::Index>(restInverses.size()) != rest.numTets()) {
    throw InvalidInputError("tetDeformationGradients: " + std::to_string(restInverses.size()) +
                            " rest inverses for " + std::to_string(rest.numTets()) + " tets");
  }
  if (deformedVertices.cols() != rest.numVertices()) {
    throw InvalidInputError("tetDeformationGradients: " + std::to_string(deformedVertices.cols()) +
                            " deformed vertices for a mesh of " + std::to_string(rest.numVertices()));
  }
  if (!deformedVertices.allFinite()) {
    throw InvalidInputError("tetDeformationGradients: deformed positions contain NaN or Inf");
  }
  Matrix3dList F(restInverses.size());
  for (Eigen::Index t = 0; t < rest.numTets(); ++t) {
    const Eigen::Vector4i tet = rest.tets.col(t);
    Eigen::Matrix3d Ds;
    for (int k = 0; k < 3; ++k) Ds.col(k) = deformedVertices.col(tet[k + 1]) - deformedVertices.col(tet[0]);
    F[static_cast<size_t>(t)] = Ds * restInverses[static_cast<size_t>(t)];  // F = Ds Dm^-1
  }
  return F;
}

Matrix3dList tetDeformationGradients(const mesh::TetMesh& rest, const Eigen::Matrix3Xd& deformedVertices) {
  return tetDeformationGradients(rest, restShapeInverses(rest), deformedVertices);
}

}  // namespace deformation_enrichment::kinematics
