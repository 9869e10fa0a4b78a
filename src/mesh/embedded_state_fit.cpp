#include "deformation_enrichment/mesh/embedded_state_fit.hpp"

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <cmath>
#include <string>

#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::mesh {
namespace {

using Sparse = Eigen::SparseMatrix<double>;

// Free-node numbering: -1 for a fixed node.
std::vector<int> freeIndex(Eigen::Index vertices, const std::vector<int>& fixed, int& freeCount) {
  std::vector<int> index(static_cast<std::size_t>(vertices), 0);
  for (int v : fixed) {
    if (v < 0 || v >= vertices)
      throw InvalidInputError("fitNodeDisplacements: fixed node " + std::to_string(v) + " is outside the mesh (" +
                              std::to_string(vertices) + " nodes)");
    index[static_cast<std::size_t>(v)] = -1;
  }
  freeCount = 0;
  for (int& i : index)
    if (i == 0) i = freeCount++;
  return index;
}

// W restricted to the free nodes (points x free).
Sparse interpolationMatrix(const TetMesh& mesh, const BarycentricEmbedding& embedding, const std::vector<int>& index, int freeCount) {
  std::vector<Eigen::Triplet<double>> entries;
  for (Eigen::Index p = 0; p < embedding.tet.size(); ++p) {
    if (embedding.tet[p] < 0) continue;
    for (int k = 0; k < 4; ++k) {
      const int column = index[static_cast<std::size_t>(mesh.tets(k, embedding.tet[p]))];
      if (column >= 0) entries.emplace_back(static_cast<int>(p), column, embedding.weights(k, p));
    }
  }
  Sparse W(embedding.tet.size(), freeCount);
  W.setFromTriplets(entries.begin(), entries.end());
  return W;
}

// G^T G restricted to the free nodes: the graph Laplacian of the tets' edges (an edge shared by tets counts
// once per tet, which weights interior edges more, as a stiffness matrix would).
Sparse edgeLaplacian(const TetMesh& mesh, const std::vector<int>& index, int freeCount) {
  std::vector<Eigen::Triplet<double>> entries;
  for (Eigen::Index t = 0; t < mesh.numTets(); ++t)
    for (int a = 0; a < 4; ++a)
      for (int b = a + 1; b < 4; ++b) {
        const int i = index[static_cast<std::size_t>(mesh.tets(a, t))], j = index[static_cast<std::size_t>(mesh.tets(b, t))];
        if (i >= 0) entries.emplace_back(i, i, 1.0);
        if (j >= 0) entries.emplace_back(j, j, 1.0);
        if (i >= 0 && j >= 0) entries.emplace_back(i, j, -1.0), entries.emplace_back(j, i, -1.0);
      }
  Sparse L(freeCount, freeCount);
  L.setFromTriplets(entries.begin(), entries.end());
  return L;
}

}  // namespace

Eigen::Matrix3Xd fitNodeDisplacements(const TetMesh& mesh, const BarycentricEmbedding& embedding,
                                      const Eigen::Matrix3Xd& displacement, const std::vector<int>& fixed, double smoothing) {
  if (displacement.cols() != embedding.tet.size())
    throw InvalidInputError("fitNodeDisplacements: " + std::to_string(displacement.cols()) + " displacements for " +
                            std::to_string(embedding.tet.size()) + " embedded points");
  if (!displacement.allFinite()) throw InvalidInputError("fitNodeDisplacements: non-finite displacement");
  if (!(smoothing > 0.0) || !std::isfinite(smoothing))
    throw InvalidInputError("fitNodeDisplacements: smoothing must be positive and finite, got " + std::to_string(smoothing));
  int freeCount = 0;
  const std::vector<int> index = freeIndex(mesh.numVertices(), fixed, freeCount);
  Eigen::Matrix3Xd u = Eigen::Matrix3Xd::Zero(3, mesh.numVertices());
  if (freeCount == 0) return u;
  const Sparse W = interpolationMatrix(mesh, embedding, index, freeCount);
  const Sparse L = edgeLaplacian(mesh, index, freeCount);
  const Sparse WtW = Sparse(W.transpose()) * W;
  const double scale = WtW.diagonal().sum() / std::max(L.diagonal().sum(), 1e-300);
  const Sparse A = WtW + (smoothing * scale) * L;
  Eigen::SimplicialLDLT<Sparse> ldlt(A);
  if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 1e-12 * ldlt.vectorD().maxCoeff()))
    throw InvalidInputError("fitNodeDisplacements: the fit has no unique solution (no fixed node reaches a part the points do not)");
  const Eigen::MatrixXd solution = ldlt.solve(Eigen::MatrixXd(W.transpose() * displacement.transpose()));
  for (std::size_t v = 0; v < index.size(); ++v)
    if (index[v] >= 0) u.col(static_cast<Eigen::Index>(v)) = solution.row(index[v]).transpose();
  return u;
}

}  // namespace deformation_enrichment::mesh
