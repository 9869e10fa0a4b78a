// Sequence validation, PCA subspaces and rigid-aware interpolation.
#include <gtest/gtest.h>

#include <limits>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/shape_space/affine_subspace.hpp"
#include "deformation_enrichment/shape_space/rigid_interpolation.hpp"
#include "deformation_enrichment/shape_space/shape_sequence.hpp"
#include "flow_test_sequences.hpp"

namespace ss = deformation_enrichment::shape_space;
namespace de = deformation_enrichment;
using ss::test::bumpyGrid;

TEST(ShapeSequence, BadInputGivesClearErrors) {
  const auto base = bumpyGrid(4, 1);
  const de::mesh::TriangleMesh m{ss::unflatten(base.vertices), base.triangles};
  EXPECT_NO_THROW(ss::makeSequence({m, m, m}));
  // fewer than 3 shapes
  try {
    ss::makeSequence({m, m});
    FAIL();
  } catch (const de::InvalidInputError& e) {
    EXPECT_NE(std::string(e.what()).find("at least 3"), std::string::npos);
  }
  // different vertex counts
  de::mesh::TriangleMesh fewer = m;
  fewer.vertices.conservativeResize(3, m.numVertices() - 1);
  try {
    ss::makeSequence({m, fewer, m});
    FAIL();
  } catch (const de::InvalidInputError& e) {
    EXPECT_NE(std::string(e.what()).find("shape 1"), std::string::npos);
  }
  // NaN
  de::mesh::TriangleMesh nan = m;
  nan.vertices(1, 3) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(ss::makeSequence({m, m, nan}), de::InvalidInputError);
  // degenerate triangle (collapse one triangle's vertices onto each other)
  de::mesh::TriangleMesh degenerate = m;
  degenerate.vertices.col(m.triangles(1, 0)) = degenerate.vertices.col(m.triangles(0, 0));
  try {
    ss::makeSequence({m, degenerate, m});
    FAIL();
  } catch (const de::InvalidInputError& e) {
    EXPECT_NE(std::string(e.what()).find("degenerate"), std::string::npos);
  }
}

TEST(AffineSubspace, PcaSpansTheShapesAndIsOrthonormal) {
  const auto base = bumpyGrid(5, 2);
  const auto shapes = ss::test::noisyBending(base, 6, 0.0, 2.0, 0.01, 3);
  const ss::AffineSubspace full = ss::pcaSubspace(shapes, 10);
  EXPECT_EQ(full.dimension(), 5);  // 6 shapes span at most 5 affine directions
  EXPECT_LT((full.basis.transpose() * full.basis - Eigen::MatrixXd::Identity(5, 5)).norm(), 1e-12);
  for (const auto& x : shapes) EXPECT_LT((full.lift(full.coordinates(x)) - x).norm(), 1e-10 * x.norm());
  // A 2-dimensional PCA keeps the directions of largest variance: its residual is the smallest possible
  // among the 5 choose 2 coordinate pairs of the full basis (which are the principal directions).
  const ss::AffineSubspace two = ss::pcaSubspace(shapes, 2);
  double residualPca = 0.0, residualOther = 0.0;
  for (const auto& x : shapes) {
    residualPca += (two.lift(two.coordinates(x)) - x).squaredNorm();
    const Eigen::MatrixXd b = full.basis.rightCols(2);
    residualOther += ((x - full.origin) - b * (b.transpose() * (x - full.origin))).squaredNorm();
  }
  EXPECT_LT(residualPca, residualOther);
  // Enrichment adds only new directions.
  ss::AffineSubspace enriched = two;
  EXPECT_EQ(ss::enrich(enriched, {full.basis.col(0), full.basis.col(3)}), 1);
  EXPECT_EQ(enriched.dimension(), 3);
  EXPECT_THROW(ss::pcaSubspace({}, 2), de::InvalidInputError);
  EXPECT_THROW(ss::pcaSubspace(shapes, 0), de::InvalidInputError);
}

TEST(RigidInterpolation, KabschRecoversMotionAndRigidCopiesInterpolateRigidly) {
  const auto base = bumpyGrid(5, 4);
  const Eigen::Matrix3d r = ss::test::someRotation(1.3);
  const Eigen::Vector3d t(0.3, -2.0, 1.0);
  const Eigen::VectorXd copy = ss::test::moved(base.vertices, r, t);
  const ss::RigidTransform found = ss::kabsch(base.vertices, copy);
  EXPECT_LT((found.rotation - r).norm(), 1e-10);
  EXPECT_LT((found.translation - t).norm(), 1e-10);
  EXPECT_LT((ss::applyRigid(found, base.vertices) - copy).norm(), 1e-10);
  for (double s : {0.0, 0.25, 0.5, 1.0}) {
    const Eigen::VectorXd mid = ss::rigidAwareInterpolation(base.vertices, copy, s);
    const ss::RigidTransform m = ss::kabsch(base.vertices, mid);
    EXPECT_LT((ss::applyRigid(m, base.vertices) - mid).norm(), 1e-10) << "s = " << s;  // still rigid
  }
  EXPECT_TRUE(ss::rigidAwareInterpolation(base.vertices, copy, 1.0) == copy);
  EXPECT_THROW(ss::rigidAwareInterpolation(base.vertices, copy, 1.5), de::InvalidInputError);
}
