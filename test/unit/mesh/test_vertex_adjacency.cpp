// One-rings of mesh::vertexAdjacency on small hand-made meshes.
#include <gtest/gtest.h>

#include <vector>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/mesh/vertex_adjacency.hpp"

using namespace deformation_enrichment;

namespace {
std::vector<int> ring(const mesh::VertexAdjacency& a, int v) { return std::vector<int>(a.begin(v), a.end(v)); }
}  // namespace

TEST(VertexAdjacency, OneRingsOfTwoTrianglesAndAnIsolatedVertex) {
  // Square 0-1-2-3 split along 0-2, vertex 4 used by no triangle.
  Eigen::Matrix3Xi triangles(3, 2);
  triangles << 0, 0,  //
      1, 2,           //
      2, 3;
  const mesh::VertexAdjacency a = mesh::vertexAdjacency(triangles, 5);
  EXPECT_EQ(a.numVertices(), 5);
  EXPECT_EQ(ring(a, 0), (std::vector<int>{1, 2, 3}));  // the shared edge 0-2 once
  EXPECT_EQ(ring(a, 1), (std::vector<int>{0, 2}));
  EXPECT_EQ(ring(a, 2), (std::vector<int>{0, 1, 3}));
  EXPECT_EQ(ring(a, 3), (std::vector<int>{0, 2}));
  EXPECT_TRUE(ring(a, 4).empty());
  EXPECT_EQ(a.neighbours.size(), 10u);  // 5 edges, both directions
}

TEST(VertexAdjacency, EmptyAndInvalidInput) {
  const mesh::VertexAdjacency none = mesh::vertexAdjacency(Eigen::Matrix3Xi(3, 0), 0);
  EXPECT_EQ(none.numVertices(), 0);
  Eigen::Matrix3Xi triangles(3, 1);
  triangles << 0, 1, 3;
  EXPECT_THROW(mesh::vertexAdjacency(triangles, 3), InvalidInputError);
  triangles(2, 0) = -1;
  EXPECT_THROW(mesh::vertexAdjacency(triangles, 3), InvalidInputError);
  EXPECT_THROW(mesh::vertexAdjacency(Eigen::Matrix3Xi(3, 0), -1), InvalidInputError);
}
