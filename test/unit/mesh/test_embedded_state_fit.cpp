#include <gtest/gtest.h>

#include <string>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/embedded_state_fit.hpp"
#include "deformation_enrichment/mesh/grid_tet_mesh.hpp"

using namespace deformation_enrichment;

namespace {

// A 4 x 4 x 3 cell box, 4 cm x 4 cm x 1.5 cm; vertex (i, j, k) has index i + 5 (j + 5 k).
mesh::TetMesh box() { return mesh::gridTetMesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0.04, 0.04, 0.015), Eigen::Vector3i(4, 4, 3)); }

std::vector<int> layer(int k) {
  std::vector<int> ids;
  for (int v = 0; v < 25; ++v) ids.push_back(v + 25 * k);
  return ids;
}

}  // namespace

TEST(EmbeddedStateFit, PointsAtTheNodesGiveTheirDisplacementBack) {
  const mesh::TetMesh m = box();
  const mesh::BarycentricEmbedding e = mesh::embedPoints(m, m.vertices, 0.0);
  Eigen::Matrix3Xd d = Eigen::Matrix3Xd::Random(3, m.numVertices()) * 1e-3;
  for (int v : layer(0)) d.col(v).setZero();
  const Eigen::Matrix3Xd u = mesh::fitNodeDisplacements(m, e, d, layer(0), 1e-10);
  EXPECT_LT((u - d).cwiseAbs().maxCoeff(), 1e-9);
}

TEST(EmbeddedStateFit, TopMotionReachesTheInteriorBetweenTheFixedBottomAndTheTop) {
  // Only the top layer's nodes are observed, pressed 1 mm down; the bottom is held. The interior layers are
  // not observed: the membrane term carries the motion down, decreasing with depth.
  const mesh::TetMesh m = box();
  const std::vector<int> top = layer(3);
  Eigen::Matrix3Xd points(3, static_cast<Eigen::Index>(top.size()));
  for (std::size_t i = 0; i < top.size(); ++i) points.col(static_cast<Eigen::Index>(i)) = m.vertices.col(top[i]);
  const mesh::BarycentricEmbedding e = mesh::embedPoints(m, points, 0.0);
  Eigen::Matrix3Xd d = Eigen::Matrix3Xd::Zero(3, points.cols());
  d.row(2).setConstant(-1e-3);
  const Eigen::Matrix3Xd u = mesh::fitNodeDisplacements(m, e, d, layer(0));
  for (int v : layer(0)) EXPECT_EQ(u.col(v).norm(), 0.0);
  const int middle = 2 + 5 * 2;  // the centre column's nodes, k = 1, 2, 3
  const double z1 = u(2, middle + 25), z2 = u(2, middle + 50), z3 = u(2, middle + 75);
  EXPECT_NEAR(z3, -1e-3, 1e-5);
  EXPECT_LT(z3, z2);
  EXPECT_LT(z2, z1);
  EXPECT_LT(z1, 0.0);
}

TEST(EmbeddedStateFit, BadInputIsRefusedWithItsProblemNamed) {
  const mesh::TetMesh m = box();
  const mesh::BarycentricEmbedding e = mesh::embedPoints(m, m.vertices.leftCols(10), 0.0);
  const Eigen::Matrix3Xd d = Eigen::Matrix3Xd::Zero(3, 10);
  const auto message = [&](const Eigen::Matrix3Xd& x, const std::vector<int>& fixed, double s) {
    try {
      mesh::fitNodeDisplacements(m, e, x, fixed, s);
    } catch (const InvalidInputError& error) {
      return std::string(error.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message(Eigen::Matrix3Xd::Zero(3, 9), layer(0), 1e-3).find("9 displacements for 10 embedded points"), std::string::npos);
  Eigen::Matrix3Xd nan = d;
  nan(1, 3) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(message(nan, layer(0), 1e-3).find("non-finite"), std::string::npos);
  EXPECT_NE(message(d, {100000}, 1e-3).find("fixed node 100000"), std::string::npos);
  EXPECT_NE(message(d, layer(0), 0.0).find("smoothing"), std::string::npos);
  // Two separate boxes, points and fixed nodes only in the first: the second's motion is undetermined.
  mesh::TetMesh two = m;
  two.vertices.conservativeResize(3, 2 * m.numVertices());
  two.vertices.rightCols(m.numVertices()) = m.vertices.colwise() + Eigen::Vector3d(1.0, 0.0, 0.0);
  two.tets.conservativeResize(4, 2 * m.numTets());
  two.tets.rightCols(m.numTets()) = m.tets.array() + static_cast<int>(m.numVertices());
  EXPECT_THROW(mesh::fitNodeDisplacements(two, e, d, layer(0)), InvalidInputError);
}
