#include "deformation_enrichment/mesh/grid_tet_mesh.hpp"

#include <array>
#include <string>

#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::mesh {
namespace {
void checkAxis(const Eigen::VectorXd& axis, const char* name) {
  if (axis.size() < 2) throw InvalidInputError(std::string("grid axis ") + name + " needs at least two coordinates");
  for (Eigen::Index i = 1; i < axis.size(); ++i) {
    if (!(axis[i] > axis[i - 1]))
      throw InvalidInputError(std::string("grid axis ") + name + " is not strictly increasing at index " +
                              std::to_string(i));
  }
}
}  // namespace

TetMesh gridTetMesh(const Eigen::VectorXd& xs, const Eigen::VectorXd& ys, const Eigen::VectorXd& zs) {
  checkAxis(xs, "x");
  checkAxis(ys, "y");
  checkAxis(zs, "z");
  const int nx = static_cast<int>(xs.size()), ny = static_cast<int>(ys.size()), nz = static_cast<int>(zs.size());
  TetMesh mesh;
  mesh.vertices.resize(3, static_cast<Eigen::Index>(nx) * ny * nz);
  auto index = [&](int i, int j, int k) { return i + nx * (j + ny * k); };
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) mesh.vertices.col(index(i, j, k)) << xs[i], ys[j], zs[k];

  // Kuhn subdivision: each of the 3! axis orders walks from corner (0,0,0) to (1,1,1) along one path
  // of three unit steps; the four visited corners form one tet. All six share the main diagonal.
  const std::array<std::array<int, 3>, 6> orders{{{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}}};
  mesh.tets.resize(4, 6 * static_cast<Eigen::Index>(nx - 1) * (ny - 1) * (nz - 1));
  Eigen::Index t = 0;
  for (int k = 0; k + 1 < nz; ++k)
    for (int j = 0; j + 1 < ny; ++j)
      for (int i = 0; i + 1 < nx; ++i)
        for (const auto& order : orders) {
          std::array<int, 3> corner{i, j, k};
          Eigen::Vector4i tet;
          tet[0] = index(corner[0], corner[1], corner[2]);
          for (int step = 0; step < 3; ++step) {
            ++corner[order[step]];
            tet[step + 1] = index(corner[0], corner[1], corner[2]);
          }
          mesh.tets.col(t) = tet;
          // Odd permutations of the axes give negatively oriented tets: swap two vertices to fix.
          if (signedVolume(mesh, t) < 0.0) std::swap(mesh.tets(2, t), mesh.tets(3, t));
          ++t;
        }
  return mesh;
}

TetMesh gridTetMesh(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, const Eigen::Vector3i& cells) {
  if ((cells.array() < 1).any()) throw InvalidInputError("grid needs at least one cell per axis");
  const Eigen::VectorXd xs = Eigen::VectorXd::LinSpaced(cells[0] + 1, lo[0], hi[0]);
  const Eigen::VectorXd ys = Eigen::VectorXd::LinSpaced(cells[1] + 1, lo[1], hi[1]);
  const Eigen::VectorXd zs = Eigen::VectorXd::LinSpaced(cells[2] + 1, lo[2], hi[2]);
  return gridTetMesh(xs, ys, zs);
}

}  // namespace deformation_enrichment::mesh
