#include "deformation_enrichment/elasticity/tet_fem.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <string>

#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::elasticity {
namespace {

constexpr double kMaxSquaredF = 1e60;  // beyond this StableNeoHookean rejects F (overflow guard)
constexpr Eigen::Index kParallelTets = 2000;  // below this, thread start-up costs more than it saves

bool isExtreme(const Eigen::Matrix3d& F) { return !F.allFinite() || F.squaredNorm() > kMaxSquaredF; }

/// Position of entry (row, col) in the value array of a compressed column-major matrix, or -1.
Eigen::Index entryIndex(const Eigen::SparseMatrix<double>& H, int row, int col) {
  const int* begin = H.innerIndexPtr() + H.outerIndexPtr()[col];
  const int* end = H.innerIndexPtr() + H.outerIndexPtr()[col + 1];
  const int* found = std::lower_bound(begin, end, row);
  if (found == end || *found != row) return -1;
  return found - H.innerIndexPtr();
}

// Tets are coloured in blocks of consecutive ones (meshes number neighbouring tets closely, so a block is
// compact and its scatter cache-friendly). Greedy: each block takes the smallest colour none of its vertices'
// earlier blocks has, so blocks of one colour share no vertex and scatter into vertex-indexed storage
// concurrently; within a block the tets go in order.
constexpr Eigen::Index kColourBlock = 32;

void colourTetBlocks(const mesh::TetMesh& mesh, std::vector<Eigen::Index>& blocks, std::vector<std::size_t>& start) {
  const Eigen::Index count = (mesh.numTets() + kColourBlock - 1) / kColourBlock;
  std::vector<std::vector<int>> coloursAt(static_cast<std::size_t>(mesh.numVertices()));
  std::vector<int> colour(static_cast<std::size_t>(count));
  std::vector<char> taken;
  int colours = 0;
  for (Eigen::Index b = 0; b < count; ++b) {
    const Eigen::Index first = b * kColourBlock, last = std::min(first + kColourBlock, mesh.numTets());
    taken.assign(static_cast<std::size_t>(colours) + 1, 0);
    for (Eigen::Index t = first; t < last; ++t)
      for (int a = 0; a < 4; ++a)
        for (int c : coloursAt[static_cast<std::size_t>(mesh.tets(a, t))]) taken[static_cast<std::size_t>(c)] = 1;
    const int c = static_cast<int>(std::find(taken.begin(), taken.end(), 0) - taken.begin());
    colour[static_cast<std::size_t>(b)] = c;
    colours = std::max(colours, c + 1);
    for (Eigen::Index t = first; t < last; ++t)
      for (int a = 0; a < 4; ++a) {
        std::vector<int>& at = coloursAt[static_cast<std::size_t>(mesh.tets(a, t))];
        if (at.empty() || at.back() != c) at.push_back(c);
      }
  }
  start.assign(static_cast<std::size_t>(colours) + 1, 0);
  for (int c : colour) ++start[static_cast<std::size_t>(c) + 1];
  for (std::size_t c = 0; c < static_cast<std::size_t>(colours); ++c) start[c + 1] += start[c];
  blocks.resize(static_cast<std::size_t>(count));
  std::vector<std::size_t> next(start.begin(), start.end() - 1);
  for (Eigen::Index b = 0; b < count; ++b) blocks[next[static_cast<std::size_t>(colour[static_cast<std::size_t>(b)])]++] = b;
}

}  // namespace

template <class Visit>
void TetFem::forEachTetByColour(const Visit& visit) const {
  const bool parallel = rest_.numTets() > kParallelTets;
  for (std::size_t c = 0; c + 1 < colourStart_.size(); ++c) {
    const auto begin = static_cast<std::ptrdiff_t>(colourStart_[c]), end = static_cast<std::ptrdiff_t>(colourStart_[c + 1]);
#pragma omp parallel for schedule(static) if (parallel)
    for (std::ptrdiff_t i = begin; i < end; ++i) {
      const Eigen::Index first = blocksByColour_[static_cast<std::size_t>(i)] * kColourBlock;
      const Eigen::Index last = std::min(first + kColourBlock, rest_.numTets());
      for (Eigen::Index t = first; t < last; ++t) visit(t);
    }
  }
}

TetFem::TetFem(const mesh::TetMesh& rest, std::vector<StableNeoHookean> materials, const Eigen::VectorXi& materialId)
    : rest_(rest), materials_(std::move(materials)), materialId_(materialId) {
  mesh::validate(rest_);
  if (materials_.empty()) throw InvalidInputError("TetFem: no materials given");
  if (materialId_.size() != rest_.numTets())
    throw InvalidInputError("TetFem: " + std::to_string(materialId_.size()) + " material ids for " +
                            std::to_string(rest_.numTets()) + " tets");
  if (materialId_.minCoeff() < 0 || materialId_.maxCoeff() >= static_cast<int>(materials_.size()))
    throw InvalidInputError("TetFem: material id out of range [0, " + std::to_string(materials_.size()) + ")");
  dmInverse_.resize(static_cast<std::size_t>(rest_.numTets()));
  restVolume_.resize(rest_.numTets());
  for (Eigen::Index t = 0; t < rest_.numTets(); ++t) {
    Eigen::Matrix3d Dm;
    for (int c = 0; c < 3; ++c) Dm.col(c) = rest_.vertices.col(rest_.tets(c + 1, t)) - rest_.vertices.col(rest_.tets(0, t));
    restVolume_[t] = Dm.determinant() / 6.0;
    dmInverse_[static_cast<std::size_t>(t)] = Dm.inverse();
    if (!dmInverse_[static_cast<std::size_t>(t)].allFinite())
      throw InvalidInputError("TetFem: rest tet " + std::to_string(t) + " is too degenerate to invert");
  }
  colourTetBlocks(rest_, blocksByColour_, colourStart_);
}

TetFem::TetFem(const mesh::TetMesh& rest, const StableNeoHookean& material)
    : TetFem(rest, std::vector<StableNeoHookean>{material}, Eigen::VectorXi::Zero(rest.numTets())) {}

double TetFem::maxShearModulus() const {
  double mu = 0.0;
  for (const auto& material : materials_) mu = std::max(mu, material.mu());
  return mu;
}

void TetFem::checkPositions(const Eigen::Matrix3Xd& x, const char* where) const {
  if (x.cols() != rest_.numVertices())
    throw InvalidInputError(std::string("TetFem::") + where + ": positions have " + std::to_string(x.cols()) +
                            " columns for " + std::to_string(rest_.numVertices()) + " vertices");
}

Eigen::Matrix3d TetFem::deformationGradient(const Eigen::Matrix3Xd& x, Eigen::Index t) const {
  Eigen::Matrix3d Ds;
  for (int c = 0; c < 3; ++c) Ds.col(c) = x.col(rest_.tets(c + 1, t)) - x.col(rest_.tets(0, t));
  return Ds * dmInverse_[static_cast<std::size_t>(t)];  // linear tet: F = Ds Dm^-1 (columns f0|f1|f2, [Masanti19 eq. 2.1])
}

Eigen::Matrix<double, 9, 12> TetFem::shapeDerivative(Eigen::Index t) const {
  // F = X G with X = [x0 x1 x2 x3] and G (4 x 3): rows 1..3 are Dm^-1, row 0 is minus their sum.
  const Eigen::Matrix3d& DmInv = dmInverse_[static_cast<std::size_t>(t)];
  Eigen::Matrix<double, 4, 3> G;
  G.bottomRows<3>() = DmInv;
  G.row(0) = -DmInv.colwise().sum();
  Eigen::Matrix<double, 9, 12> B = Eigen::Matrix<double, 9, 12>::Zero();
  for (int a = 0; a < 4; ++a)
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) B(i + 3 * j, 3 * a + i) = G(a, j);
  return B;
}

double TetFem::energy(const Eigen::Matrix3Xd& x) const {
  checkPositions(x, "energy");
  // Terms in parallel, summed in tet order: the same sum on any number of threads.
  Eigen::VectorXd terms(rest_.numTets());
  bool finite = true;
#pragma omp parallel for reduction(&& : finite) schedule(static) if (rest_.numTets() > kParallelTets)
  for (Eigen::Index t = 0; t < rest_.numTets(); ++t) {
    const Eigen::Matrix3d F = deformationGradient(x, t);
    if (isExtreme(F)) {
      finite = false;
      terms[t] = 0.0;
      continue;
    }
    terms[t] = restVolume_[t] * material(t).psi(F);
  }
  double total = 0.0;
  for (Eigen::Index t = 0; t < rest_.numTets(); ++t) total += terms[t];
  return finite && std::isfinite(total) ? total : std::numeric_limits<double>::infinity();
}

Eigen::VectorXd TetFem::gradient(const Eigen::Matrix3Xd& x) const {
  checkPositions(x, "gradient");
  Eigen::VectorXd g = Eigen::VectorXd::Zero(3 * rest_.numVertices());
  std::atomic<bool> extreme = false;
  forEachTetByColour([&](Eigen::Index t) {
    const Eigen::Matrix3d F = deformationGradient(x, t);
    if (isExtreme(F)) {  // exceptions must not leave an OpenMP region: flag and throw after it
      extreme = true;
      return;
    }
    // dE/dx = V P : dF/dx (vec(P) is column-major like vec(F)).
    const Eigen::Matrix3d P = material(t).pk1(F);
    const Eigen::Matrix<double, 12, 1> local =
        restVolume_[t] * shapeDerivative(t).transpose() * Eigen::Map<const Eigen::Matrix<double, 9, 1>>(P.data());
    for (int a = 0; a < 4; ++a)
      for (int i = 0; i < 3; ++i) g[3 * rest_.tets(a, t) + i] += local[3 * a + i];
  });
  if (extreme) throw InvalidInputError("TetFem::gradient: positions give a non-finite or overflowing deformation gradient");
  return g;
}

Eigen::SparseMatrix<double> TetFem::reducedPattern(const Eigen::VectorXi& dofMap, bool lowerOnly) const {
  const Eigen::Index V = rest_.numVertices();
  if (dofMap.size() != 3 * V) throw InvalidInputError("TetFem: dof map must have 3 entries per vertex");
  const int n = dofMap.maxCoeff() + 1;
  std::vector<int> columnDof(static_cast<std::size_t>(std::max(n, 0)), -1);
  for (Eigen::Index d = 0; d < dofMap.size(); ++d) {
    const int r = dofMap[d];
    if (r < -1 || r >= n || (r >= 0 && columnDof[static_cast<std::size_t>(r)] != -1))
      throw InvalidInputError("TetFem: dof map is not a one-to-one numbering of the free dofs");
    if (r >= 0) columnDof[static_cast<std::size_t>(r)] = static_cast<int>(d);
  }
  // Vertex adjacency through shared tets decides which 3x3 blocks are non-zero.
  std::vector<std::vector<int>> neighbours(static_cast<std::size_t>(V));
  for (Eigen::Index t = 0; t < rest_.numTets(); ++t)
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b) neighbours[static_cast<std::size_t>(rest_.tets(a, t))].push_back(rest_.tets(b, t));
  for (auto& list : neighbours) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }
  std::vector<int> outer(static_cast<std::size_t>(n) + 1, 0);
  std::vector<int> inner;
  std::vector<int> rows;
  for (int c = 0; c < n; ++c) {
    const int vertex = columnDof[static_cast<std::size_t>(c)] / 3;
    rows.clear();
    for (int u : neighbours[static_cast<std::size_t>(vertex)])
      for (int k = 0; k < 3; ++k) {
        const int r = dofMap[3 * u + k];
        if (r >= 0 && (!lowerOnly || r >= c)) rows.push_back(r);
      }
    std::sort(rows.begin(), rows.end());
    inner.insert(inner.end(), rows.begin(), rows.end());
    outer[static_cast<std::size_t>(c) + 1] = static_cast<int>(inner.size());
  }
  std::vector<double> zeros(inner.size(), 0.0);
  Eigen::Map<const Eigen::SparseMatrix<double>> view(n, n, static_cast<Eigen::Index>(inner.size()), outer.data(),
                                                      inner.data(), zeros.data());
  return Eigen::SparseMatrix<double>(view);
}

void TetFem::assembleReduced(const Eigen::Matrix3Xd& x, const Eigen::VectorXi& dofMap, bool lowerOnly,
                             HessianKind kind, Eigen::SparseMatrix<double>& H, Eigen::VectorXd* gradient) const {
  checkPositions(x, "assembleReduced");
  if (dofMap.size() != 3 * rest_.numVertices()) throw InvalidInputError("TetFem: dof map must have 3 entries per vertex");
  const int n = dofMap.maxCoeff() + 1;
  if (H.rows() != n || H.cols() != n || !H.isCompressed())
    throw InvalidInputError("TetFem::assembleReduced: H was not built by reducedPattern for this dof map");
  std::fill(H.valuePtr(), H.valuePtr() + H.nonZeros(), 0.0);
  if (gradient) gradient->setZero(n);
  std::atomic<bool> patternMismatch = false, extreme = false;
  forEachTetByColour([&](Eigen::Index t) {
    const Eigen::Matrix3d F = deformationGradient(x, t);
    if (isExtreme(F)) {  // exceptions must not leave an OpenMP region: flag and throw after it
      extreme = true;
      return;
    }
    const StableNeoHookean& psi = material(t);
    const Eigen::Matrix<double, 9, 12> B = shapeDerivative(t);
    // Element Hessian V B^T (d^2 Psi / dF^2) B (chain rule through the linear map x -> vec(F)).
    const Matrix9d H9 = kind == HessianKind::Projected ? psi.projectedHessian(F) : psi.hessian(F);
    const Eigen::Matrix<double, 12, 12> local = restVolume_[t] * B.transpose() * H9 * B;
    int dof[12];
    for (int a = 0; a < 4; ++a)
      for (int i = 0; i < 3; ++i) dof[3 * a + i] = dofMap[3 * rest_.tets(a, t) + i];
    for (int q = 0; q < 12; ++q) {
      if (dof[q] < 0) continue;
      for (int p = 0; p < 12; ++p) {
        if (dof[p] < 0 || (lowerOnly && dof[p] < dof[q])) continue;
        const Eigen::Index at = entryIndex(H, dof[p], dof[q]);
        if (at < 0) {
          patternMismatch = true;
          continue;
        }
        H.valuePtr()[at] += local(p, q);
      }
    }
    if (gradient) {
      const Eigen::Matrix3d P = psi.pk1(F);
      const Eigen::Matrix<double, 12, 1> g = restVolume_[t] * B.transpose() * Eigen::Map<const Vector9d>(P.data());
      for (int p = 0; p < 12; ++p)
        if (dof[p] >= 0) (*gradient)[dof[p]] += g[p];
    }
  });
  if (extreme)
    throw InvalidInputError("TetFem::assembleReduced: positions give a non-finite or overflowing deformation gradient");
  if (patternMismatch) throw InvalidInputError("TetFem::assembleReduced: H was not built by reducedPattern for this dof map");
}

Eigen::SparseMatrix<double> TetFem::hessian(const Eigen::Matrix3Xd& x, HessianKind kind) const {
  const Eigen::VectorXi identity = Eigen::VectorXi::LinSpaced(3 * rest_.numVertices(), 0, 3 * static_cast<int>(rest_.numVertices()) - 1);
  Eigen::SparseMatrix<double> H = reducedPattern(identity, false);
  assembleReduced(x, identity, false, kind, H, nullptr);
  return H;
}

Eigen::VectorXi makeDofMap(Eigen::Index vertexCount, const std::vector<int>& constrainedVertices, int* freeCount) {
  std::vector<char> constrained(static_cast<std::size_t>(vertexCount), 0);
  for (int v : constrainedVertices) {
    if (v < 0 || v >= vertexCount)
      throw InvalidInputError("constrained vertex " + std::to_string(v) + " out of range [0, " + std::to_string(vertexCount) + ")");
    constrained[static_cast<std::size_t>(v)] = 1;
  }
  Eigen::VectorXi map(3 * vertexCount);
  int next = 0;
  for (Eigen::Index v = 0; v < vertexCount; ++v)
    for (int i = 0; i < 3; ++i) map[3 * v + i] = constrained[static_cast<std::size_t>(v)] ? -1 : next++;
  if (freeCount) *freeCount = next;
  return map;
}

}  // namespace deformation_enrichment::elasticity
