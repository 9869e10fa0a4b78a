#include "deformation_enrichment/mesh/tet_refinement.hpp"

#include <array>
#include <cmath>
#include <map>
#include <utility>
#include <vector>

#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::mesh {
namespace {

// One 1:8 round [Bey95]: corners a,b,c,d and the midpoints of their six edges.
TetMesh refineOnce(const TetMesh& mesh) {
  std::map<std::pair<int, int>, int> midpointOf;
  std::vector<Eigen::Vector3d> added;
  const auto midpoint = [&](int a, int b) {
    const std::pair<int, int> edge = a < b ? std::make_pair(a, b) : std::make_pair(b, a);
    const auto [it, inserted] = midpointOf.emplace(edge, static_cast<int>(mesh.numVertices() + static_cast<Eigen::Index>(added.size())));
    if (inserted) added.push_back(0.5 * (mesh.vertices.col(a) + mesh.vertices.col(b)));
    return it->second;
  };
  std::vector<std::array<int, 4>> children;
  for (Eigen::Index t = 0; t < mesh.numTets(); ++t) {
    const int a = mesh.tets(0, t), b = mesh.tets(1, t), c = mesh.tets(2, t), d = mesh.tets(3, t);
    const int ab = midpoint(a, b), ac = midpoint(a, c), ad = midpoint(a, d), bc = midpoint(b, c), bd = midpoint(b, d), cd = midpoint(c, d);
    children.push_back({a, ab, ac, ad});
    children.push_back({ab, b, bc, bd});
    children.push_back({ac, bc, c, cd});
    children.push_back({ad, bd, cd, d});
    // The octahedron ab ac ad bc bd cd: its three diagonals join opposite midpoints; the shortest keeps the
    // children's shapes best. Around the diagonal (p, q) lie the four other midpoints in a cycle.
    const std::array<std::array<int, 6>, 3> cuts{{{ab, cd, ac, ad, bd, bc}, {ac, bd, ab, bc, cd, ad}, {ad, bc, ab, ac, cd, bd}}};
    const auto length = [&](int p, int q) {
      const auto position = [&](int v) -> Eigen::Vector3d {
        return v < mesh.numVertices() ? Eigen::Vector3d(mesh.vertices.col(v)) : added[static_cast<std::size_t>(v - mesh.numVertices())];
      };
      return (position(p) - position(q)).squaredNorm();
    };
    std::size_t best = 0;
    for (std::size_t k = 1; k < 3; ++k)
      if (length(cuts[k][0], cuts[k][1]) < length(cuts[best][0], cuts[best][1])) best = k;
    const std::array<int, 6>& cut = cuts[best];
    for (int k = 0; k < 4; ++k) children.push_back({cut[0], cut[1], cut[2 + k], cut[2 + (k + 1) % 4]});
  }
  TetMesh out;
  out.vertices.resize(3, mesh.numVertices() + static_cast<Eigen::Index>(added.size()));
  out.vertices.leftCols(mesh.numVertices()) = mesh.vertices;
  for (std::size_t k = 0; k < added.size(); ++k) out.vertices.col(mesh.numVertices() + static_cast<Eigen::Index>(k)) = added[k];
  out.tets.resize(4, static_cast<Eigen::Index>(children.size()));
  for (std::size_t t = 0; t < children.size(); ++t) {
    out.tets.col(static_cast<Eigen::Index>(t)) = Eigen::Map<const Eigen::Vector4i>(children[t].data());
    if (signedVolume(out, static_cast<Eigen::Index>(t)) < 0.0) std::swap(out.tets(0, static_cast<Eigen::Index>(t)), out.tets(1, static_cast<Eigen::Index>(t)));
  }
  return out;
}

}  // namespace

TetMesh refineTets(const TetMesh& mesh, int levels) {
  validate(mesh);
  if (levels < 0) throw InvalidInputError("refineTets: levels must be >= 0, got " + std::to_string(levels));
  TetMesh refined = mesh;
  for (int level = 0; level < levels; ++level) refined = refineOnce(refined);
  return refined;
}

int refinementLevels(const TetMesh& mesh, double maxVolume) {
  validate(mesh);
  if (!(maxVolume > 0.0)) throw InvalidInputError("refinementLevels: the largest tet volume must be positive");
  double mean = totalVolume(mesh) / static_cast<double>(mesh.numTets());
  int levels = 0;
  for (; mean > maxVolume; mean /= 8.0) ++levels;
  return levels;
}

}  // namespace deformation_enrichment::mesh
