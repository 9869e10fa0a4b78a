#include "deformation_enrichment/shape_space/discrete_shells.hpp"

#include <algorithm>
#include <array>
#include <memory>
#include <cmath>
#include <string>
#include <tuple>
#include <utility>

#include <Eigen/Geometry>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/shape_space/dihedral_angle.hpp"
#include "shell_elements.hpp"

namespace deformation_enrichment::shape_space {

namespace {

using detail::HessianPattern;
using detail::kDegenerateAreaRatio;
using detail::kParallelVertices;
using detail::LocalEdge;
using detail::LocalTerm;


// The internal need flags of an output request.
unsigned needOf(const EnergyOutputs& outputs) {
  return (outputs.value ? detail::kValue : 0u) | (outputs.gradientDeformed ? detail::kGradientDeformed : 0u) |
         (outputs.gradientReference ? detail::kGradientReference : 0u) |
         (outputs.hessianDeformed ? detail::kHessianDeformed : 0u) | (outputs.hessianMixed ? detail::kHessianMixed : 0u) |
         (outputs.hessianReference ? detail::kHessianReference : 0u);
}

// Per-thread accumulators, merged after the parallel loops. Hessian values are written straight into the
// compressed storage of the fixed sparsity pattern (thread 0 into the result, the others into buffers).
struct Accumulator {
  bool active = false;  // the runtime may start fewer threads than asked (nested regions, dynamic teams)
  double value = 0.0;
  Eigen::VectorXd gradientDeformed, gradientReference;
  Eigen::VectorXd ownDeformed, ownMixed, ownReference;  // buffers of threads > 0
  double* hessianDeformed = nullptr;
  double* hessianMixed = nullptr;
  double* hessianReference = nullptr;
};

// The three Hessian blocks (deformed, mixed, reference) of EnergyOutputs and the need bit of each.
constexpr unsigned kBlockNeeds[3] = {detail::kHessianDeformed, detail::kHessianMixed, detail::kHessianReference};

// Thread `thread`'s accumulator: gradients zeroed, Hessian values written straight into the blocks by
// thread 0 and into zeroed buffers of the blocks' size by the others (summed by reduceAccumulators).
void startAccumulator(Accumulator& acc, int thread, unsigned need, Eigen::Index dofs, Eigen::SparseMatrix<double>* const blocks[3]) {
  acc.active = true;
  if (need & detail::kGradientDeformed) acc.gradientDeformed = Eigen::VectorXd::Zero(dofs);
  if (need & detail::kGradientReference) acc.gradientReference = Eigen::VectorXd::Zero(dofs);
  Eigen::VectorXd* const own[3] = {&acc.ownDeformed, &acc.ownMixed, &acc.ownReference};
  double** const target[3] = {&acc.hessianDeformed, &acc.hessianMixed, &acc.hessianReference};
  for (int b = 0; b < 3; ++b) {
    if (!(need & kBlockNeeds[b])) continue;
    if (thread == 0) {
      *target[b] = blocks[b]->valuePtr();
    } else {
      *own[b] = Eigen::VectorXd::Zero(blocks[b]->nonZeros());
      *target[b] = own[b]->data();
    }
  }
}

// Sums the threads' values, gradients and Hessian buffers into the outputs (in thread order: deterministic
// for a given thread count).
void reduceAccumulators(const std::vector<Accumulator>& accumulators, const EnergyOutputs& outputs, unsigned need, Eigen::Index dofs,
                        Eigen::SparseMatrix<double>* const blocks[3]) {
  if (outputs.value) *outputs.value = 0.0;
  if (outputs.gradientDeformed) outputs.gradientDeformed->setZero(dofs);
  if (outputs.gradientReference) outputs.gradientReference->setZero(dofs);
  for (std::size_t t = 0; t < accumulators.size(); ++t) {
    const Accumulator& acc = accumulators[t];
    if (!acc.active) continue;
    if (outputs.value) *outputs.value += acc.value;
    if (outputs.gradientDeformed) *outputs.gradientDeformed += acc.gradientDeformed;
    if (outputs.gradientReference) *outputs.gradientReference += acc.gradientReference;
    if (t == 0) continue;
    const Eigen::VectorXd* const own[3] = {&acc.ownDeformed, &acc.ownMixed, &acc.ownReference};
    for (int b = 0; b < 3; ++b) {
      if (need & kBlockNeeds[b]) {
        Eigen::Map<Eigen::VectorXd>(blocks[b]->valuePtr(), blocks[b]->nonZeros()) += *own[b];
      }
    }
  }
}

template <int NV>
void scatter(const LocalTerm<NV>& term, const std::array<int, NV>& vertices, unsigned need,
             const HessianPattern& pattern, Accumulator& acc) {
  acc.value += term.value;
  for (int a = 0; a < NV; ++a) {
    if (need & detail::kGradientDeformed) acc.gradientDeformed.segment<3>(3 * vertices[a]) += term.gradientDeformed.template segment<3>(3 * a);
    if (need & detail::kGradientReference) acc.gradientReference.segment<3>(3 * vertices[a]) += term.gradientReference.template segment<3>(3 * a);
  }
  if (need & detail::kHessianDeformed) detail::scatterHessian<NV>(term.hessianDeformed, vertices, pattern, acc.hessianDeformed);
  if (need & detail::kHessianMixed) detail::scatterHessian<NV>(term.hessianMixed, vertices, pattern, acc.hessianMixed);
  if (need & detail::kHessianReference) detail::scatterHessian<NV>(term.hessianReference, vertices, pattern, acc.hessianReference);
}

template <int NV>
std::array<Eigen::Vector3d, NV> gather(const Eigen::VectorXd& shape, const std::array<int, NV>& vertices) {
  std::array<Eigen::Vector3d, NV> x;
  for (int a = 0; a < NV; ++a) x[a] = shape.segment<3>(3 * vertices[a]);
  return x;
}

// Bending term of one hinge: b = (theta - theta_bar)^2 w_bar, w_bar = c |e_bar|^2 / (A_bar_1 + A_bar_2),
// differentiated by the product rule (theta from the deformed, theta_bar and w_bar from the reference shape).
void addHingeTerm(const std::array<Eigen::Vector3d, 4>& x, const std::array<Eigen::Vector3d, 4>& xBar, double c,
                  double weight, unsigned need, LocalTerm<4>& out) {
  const bool needDeformedAngle = (need & (detail::kGradientDeformed | detail::kHessianDeformed | detail::kHessianMixed)) != 0u;
  const bool needReferenceDerivatives = (need & (detail::kGradientReference | detail::kHessianMixed | detail::kHessianReference)) != 0u;
  // The angle difference is taken modulo 2 pi into [-pi, pi]: a hinge folding through +-pi changes by a
  // little, not by 2 pi (the derivatives are unaffected; the shift is locally constant). One atan2 of the
  // rotation between the two hinges gives it directly (measured: atan2 was a third of a value pass).
  const double d = dihedralAngleDifference(dihedralAngleVector(x[0], x[1], x[2], x[3]),
                                           dihedralAngleVector(xBar[0], xBar[1], xBar[2], xBar[3]));
  // Angle derivatives only when needed (a HingeAngle carries a 12 x 12 Hessian). Without the Hessian only the
  // gradient is filled (the HingeAngle Hessian stays unread). The angle Hessians enter multiplied by d, so they
  // are skipped where d = 0, e.g. at the rest shape (the rest Hessians of eq. 9 and the geodesic's model).
  const bool angleHessians = d != 0.0;
  HingeAngle theta, thetaBar;
  if ((need & detail::kHessianDeformed) && angleHessians) {
    theta = dihedralAngleDerivatives(x[0], x[1], x[2], x[3], true);
  } else if (needDeformedAngle) {
    theta.gradient = dihedralAngleGradient(x[0], x[1], x[2], x[3]);
  }
  if ((need & detail::kHessianReference) && angleHessians) {
    thetaBar = dihedralAngleDerivatives(xBar[0], xBar[1], xBar[2], xBar[3], true);
  } else if (needReferenceDerivatives) {
    thetaBar.gradient = dihedralAngleGradient(xBar[0], xBar[1], xBar[2], xBar[3]);
  }
  // w_bar and its derivatives: a function of five reference squared lengths (no deformed ones).
  double wBar = 0.0;
  Eigen::Matrix<double, 12, 1> wGradient;  // d w_bar / d x_bar (read only with reference derivatives)
  Eigen::Matrix<double, 12, 12> wHessian;  // read only with kHessianReference
  if (need & detail::kHessianReference) {  // second order: forward differentiation in the squared lengths
    static constexpr std::array<LocalEdge, 0> kNoEdges{};
    static constexpr std::array<LocalEdge, 5> kHingeEdges{{{0, 1}, {1, 2}, {2, 0}, {0, 3}, {3, 1}}};
    const unsigned weightNeed = detail::kValue | detail::kGradientReference | detail::kHessianReference;
    LocalTerm<4> w(weightNeed);
    detail::addSquaredLengthTerm<4, 0, 5>([c](const auto& q) { return detail::hingeWeight(q, c); }, x, xBar, kNoEdges,
                                          kHingeEdges, weightNeed, 1.0, w);
    wBar = w.value;
    wGradient = w.gradientReference;
    wHessian = w.hessianReference;
  } else {
    wBar = detail::hingeWeightAndGradient(xBar, c, needReferenceDerivatives ? &wGradient : nullptr);
  }
  out.value += weight * d * d * wBar;
  if (need & detail::kGradientDeformed) out.gradientDeformed += weight * 2.0 * d * wBar * theta.gradient;
  if (need & detail::kGradientReference) {
    out.gradientReference += weight * (-2.0 * d * wBar * thetaBar.gradient + d * d * wGradient);
  }
  if (need & detail::kHessianDeformed) {
    out.hessianDeformed += weight * 2.0 * wBar * theta.gradient * theta.gradient.transpose();
    if (angleHessians) out.hessianDeformed += weight * 2.0 * wBar * d * theta.hessian;
  }
  if (need & detail::kHessianMixed) {
    out.hessianMixed += weight * 2.0 * (d * wGradient - wBar * thetaBar.gradient) * theta.gradient.transpose();
  }
  if (need & detail::kHessianReference) {
    const Eigen::Matrix<double, 12, 12> cross = thetaBar.gradient * wGradient.transpose();
    out.hessianReference += weight * (2.0 * wBar * thetaBar.gradient * thetaBar.gradient.transpose() -
                                      2.0 * d * (cross + cross.transpose()) + d * d * wHessian);
    if (angleHessians) out.hessianReference -= weight * 2.0 * d * wBar * thetaBar.hessian;
  }
}

}  // namespace

DiscreteShellsOptions DiscreteShellsOptions::classic() {
  DiscreteShellsOptions p;
  p.membrane = MembraneModel::DiscreteShells;
  p.lengthWeight = 0.5;
  p.areaWeight = 0.5;
  p.bendingWeight = 1.0;
  return p;
}

DiscreteShellsOptions DiscreteShellsOptions::hyperelastic(double delta) {
  DiscreteShellsOptions p;
  p.membrane = MembraneModel::Hyperelastic;
  p.mu = 1.0;
  p.lambda = 1.0;
  p.bendingWeight = delta;
  return p;
}

DiscreteShellsOptions DiscreteShellsOptions::hyperelasticFor(const Eigen::VectorXd& shape) {
  const Eigen::Map<const Eigen::Matrix3Xd> v(shape.data(), 3, shape.size() / 3);
  const double diagonal = v.cols() > 0 ? (v.rowwise().maxCoeff() - v.rowwise().minCoeff()).norm() : 0.0;
  if (!(std::isfinite(diagonal) && diagonal > 0.0))
    throw InvalidInputError("DiscreteShells: the shape has no extent (bounding-box diagonal " + std::to_string(diagonal) + ")");
  constexpr double kFingerDiagonal = 5.1313;  // [finger]: finger0.ply, where GOAST uses delta = 1e-3
  const double relative = diagonal / kFingerDiagonal;
  return hyperelastic(1e-3 * relative * relative);
}

DiscreteShells::DiscreteShells(const Eigen::Matrix3Xi& triangles, Eigen::Index numVertices,
                               const DiscreteShellsOptions& parameters)
    : triangles_(triangles), numVertices_(numVertices), parameters_(parameters) {
  if (triangles.cols() == 0 || numVertices <= 0) {
    throw InvalidInputError("DiscreteShells: the mesh is empty (" + std::to_string(triangles.cols()) +
                            " triangles, " + std::to_string(numVertices) + " vertices)");
  }
  for (const double p : {parameters.lengthWeight, parameters.areaWeight, parameters.mu, parameters.lambda,
                         parameters.bendingWeight}) {
    if (!std::isfinite(p) || p < 0.0) {
      throw InvalidInputError("DiscreteShells: parameters must be finite and non-negative, got " + std::to_string(p));
    }
  }
  if (parameters.membrane == MembraneModel::Hyperelastic && !(parameters.mu > 0.0 || parameters.lambda > 0.0)) {
    throw InvalidInputError("DiscreteShells: hyperelastic membrane needs mu > 0 or lambda > 0");
  }
  std::vector<std::tuple<int, int, int>> halfEdges;  // (min vertex, max vertex, triangle)
  halfEdges.reserve(3 * triangles.cols());
  for (Eigen::Index t = 0; t < triangles.cols(); ++t) {
    for (int a = 0; a < 3; ++a) {
      const int v = triangles(a, t);
      if (v < 0 || v >= numVertices) {
        throw InvalidInputError("DiscreteShells: triangle " + std::to_string(t) + " has vertex index " +
                                std::to_string(v) + " outside [0, " + std::to_string(numVertices) + ")");
      }
    }
    if (triangles(0, t) == triangles(1, t) || triangles(1, t) == triangles(2, t) || triangles(0, t) == triangles(2, t)) {
      throw InvalidInputError("DiscreteShells: triangle " + std::to_string(t) + " repeats a vertex");
    }
    for (int a = 0; a < 3; ++a) {
      const int u = triangles(a, t), v = triangles((a + 1) % 3, t);
      halfEdges.emplace_back(std::min(u, v), std::max(u, v), static_cast<int>(t));
    }
  }
  std::sort(halfEdges.begin(), halfEdges.end());
  for (std::size_t begin = 0; begin < halfEdges.size();) {
    std::size_t end = begin;
    while (end < halfEdges.size() && std::get<0>(halfEdges[end]) == std::get<0>(halfEdges[begin]) &&
           std::get<1>(halfEdges[end]) == std::get<1>(halfEdges[begin])) {
      ++end;
    }
    const int u = std::get<0>(halfEdges[begin]), v = std::get<1>(halfEdges[begin]);
    edges_.emplace_back(u, v);
    if (end - begin == 1) {
      ++numBoundaryEdges_;
    } else if (end - begin > 2) {
      ++numNonManifoldEdges_;
    } else {
      const int t1 = std::get<2>(halfEdges[begin]), t2 = std::get<2>(halfEdges[begin + 1]);
      // Orient the hinge edge as it runs in the first triangle: (i, j, k) in that triangle's winding.
      int a = 0;
      while (!((triangles(a, t1) == u || triangles(a, t1) == v) &&
               (triangles((a + 1) % 3, t1) == u || triangles((a + 1) % 3, t1) == v))) {
        ++a;
      }
      const int i = triangles(a, t1), j = triangles((a + 1) % 3, t1), k = triangles((a + 2) % 3, t1);
      int l = triangles(0, t2);
      for (int b = 0; b < 3; ++b) {
        if (triangles(b, t2) != u && triangles(b, t2) != v) l = triangles(b, t2);
      }
      if (l != k) {
        hinges_.emplace_back(i, j, k, l);
      } else {
        ++numNonManifoldEdges_;  // a duplicated triangle: no hinge to bend
      }
    }
    begin = end;
  }
  buildHessianPattern();
#ifdef _OPENMP
  threads_ = omp_get_max_threads();
#endif
}

void DiscreteShells::buildHessianPattern() {
  std::vector<std::vector<int>> sets(static_cast<std::size_t>(numVertices_));
  for (Eigen::Index v = 0; v < numVertices_; ++v) sets[v].push_back(static_cast<int>(v));
  for (Eigen::Index t = 0; t < triangles_.cols(); ++t) {
    for (int a = 0; a < 3; ++a) {
      for (int b = 0; b < 3; ++b) sets[triangles_(a, t)].push_back(triangles_(b, t));
    }
  }
  for (const Eigen::Vector4i& hinge : hinges_) {  // the two opposite corners couple through the angle
    sets[hinge[2]].push_back(hinge[3]);
    sets[hinge[3]].push_back(hinge[2]);
  }
  pattern_.neighbourStart.assign(1, 0);
  pattern_.neighbours.clear();
  for (auto& set : sets) {
    std::sort(set.begin(), set.end());
    set.erase(std::unique(set.begin(), set.end()), set.end());
    pattern_.neighbours.insert(pattern_.neighbours.end(), set.begin(), set.end());
    pattern_.neighbourStart.push_back(static_cast<int>(pattern_.neighbours.size()));
  }
  const Eigen::Index dofs = 3 * numVertices_;
  Eigen::VectorXi columnSizes(dofs);
  for (Eigen::Index v = 0; v < numVertices_; ++v) columnSizes.segment<3>(3 * v).setConstant(3 * static_cast<int>(sets[v].size()));
  pattern_.zeros.resize(dofs, dofs);
  pattern_.zeros.reserve(columnSizes);
  for (Eigen::Index v = 0; v < numVertices_; ++v) {
    for (int d = 0; d < 3; ++d) {
      for (const int u : sets[v]) {
        for (int r = 0; r < 3; ++r) pattern_.zeros.insert(3 * u + r, 3 * v + d) = 0.0;
      }
    }
  }
  pattern_.zeros.makeCompressed();
  pattern_.outer.assign(pattern_.zeros.outerIndexPtr(), pattern_.zeros.outerIndexPtr() + dofs + 1);
}

std::unique_ptr<DeformationEnergy> DiscreteShells::onTriangles(const Eigen::Matrix3Xi& triangles,
                                                               Eigen::Index numVertices) const {
  auto energy = std::make_unique<DiscreteShells>(triangles, numVertices, parameters_);
  energy->setThreadCount(threads_);
  return energy;
}

void DiscreteShells::setThreadCount(int threads) {
  if (threads < 1) throw InvalidInputError("DiscreteShells: thread count must be >= 1, got " + std::to_string(threads));
  threads_ = threads;
}

void DiscreteShells::checkShape(const Eigen::VectorXd& shape) const {
  DeformationEnergy::checkShape(shape);
  checkTriangles(shape, "given");
}

void DiscreteShells::checkTriangles(const Eigen::VectorXd& shape, const char* name) const {
  for (Eigen::Index t = 0; t < triangles_.cols(); ++t) {
    const Eigen::Vector3d x0 = shape.segment<3>(3 * triangles_(0, t));
    const Eigen::Vector3d x1 = shape.segment<3>(3 * triangles_(1, t));
    const Eigen::Vector3d x2 = shape.segment<3>(3 * triangles_(2, t));
    const double doubleAreaSquared = (x1 - x0).cross(x2 - x0).squaredNorm();  // squared: no square root per triangle
    const double bound = 2.0 * kDegenerateAreaRatio * ((x1 - x0).squaredNorm() + (x2 - x1).squaredNorm() + (x0 - x2).squaredNorm());
    if (!(doubleAreaSquared > bound * bound))
      throwDegenerate(t, std::string("the ") + name + " shape", 0.5 * std::sqrt(doubleAreaSquared));
  }
}

void DiscreteShells::throwDegenerate(Eigen::Index t, const std::string& shape, double area) const {
  throw InvalidInputError("DiscreteShells: triangle " + std::to_string(t) + " (vertices " + std::to_string(triangles_(0, t)) +
                          ", " + std::to_string(triangles_(1, t)) + ", " + std::to_string(triangles_(2, t)) + ") of " +
                          shape + " is degenerate (area " + std::to_string(area) + ")");
}

void DiscreteShells::assemble(const Eigen::VectorXd& reference, const Eigen::VectorXd& deformed,
                              const EnergyOutputs& outputs, unsigned parts) const {
  checkShapes(reference, deformed);
  checkTriangles(reference, "reference");
  checkTriangles(deformed, "deformed");
  const unsigned need = needOf(outputs);
  if (need == 0u) return;
  const Eigen::Index dofs = 3 * numVertices_;
  const bool hyperelastic = parameters_.membrane == MembraneModel::Hyperelastic;
  const double hingeFactor = hyperelastic ? 1.0 : 3.0;
  const DiscreteShellsOptions& p = parameters_;
  static constexpr std::array<LocalEdge, 3> kTriangleEdges{{{1, 2}, {2, 0}, {0, 1}}};  // edge m opposite corner m
  static constexpr std::array<LocalEdge, 1> kEdge{{{0, 1}}};

  Eigen::SparseMatrix<double>* const blocks[3] = {outputs.hessianDeformed, outputs.hessianMixed, outputs.hessianReference};
  for (int b = 0; b < 3; ++b) {
    if (need & kBlockNeeds[b]) *blocks[b] = pattern_.zeros;
  }
  std::vector<Accumulator> accumulators(static_cast<std::size_t>(threads_));
  const Eigen::Index numFaces = (parts & kMembrane) ? triangles_.cols() : 0;
  const Eigen::Index numEdgeTerms = ((parts & kMembrane) && !hyperelastic) ? numEdges() : 0;
  const Eigen::Index numHingeTerms = (parts & kBending) && p.bendingWeight > 0.0 ? numHinges() : 0;

#pragma omp parallel num_threads(threads_) if (numVertices_ >= kParallelVertices)
  {
#ifdef _OPENMP
    const int thread = omp_get_thread_num();
#else
    const int thread = 0;
#endif
    Accumulator& acc = accumulators[static_cast<std::size_t>(thread)];
    startAccumulator(acc, thread, need, dofs, blocks);
#pragma omp for schedule(static) nowait
    for (Eigen::Index t = 0; t < numFaces; ++t) {
      const std::array<int, 3> v{triangles_(0, t), triangles_(1, t), triangles_(2, t)};
      const auto x = gather<3>(deformed, v);
      const auto xBar = gather<3>(reference, v);
      LocalTerm<3> term(need);
      if (hyperelastic && !(need & (detail::kHessianMixed | detail::kHessianReference))) {
        detail::addHyperelasticFace(x, xBar, p.mu, p.lambda, need, term);  // [Heeren12 eq. 8] in closed form
      } else if (hyperelastic) {  // [Heeren12 eq. 8]
        detail::addSquaredLengthTerm<3, 3, 3>([&p](const auto& q) { return detail::hyperelasticMembrane(q, p.mu, p.lambda); },
                                              x, xBar, kTriangleEdges, kTriangleEdges, need, 1.0, term);
      } else {  // [Grinspun03] area term
        detail::addSquaredLengthTerm<3, 3, 3>([&p](const auto& q) { return detail::discreteShellsArea(q, p.areaWeight); },
                                              x, xBar, kTriangleEdges, kTriangleEdges, need, 1.0, term);
      }
      scatter<3>(term, v, need, pattern_, acc);
    }
#pragma omp for schedule(static) nowait
    for (Eigen::Index e = 0; e < numEdgeTerms; ++e) {  // [Grinspun03] edge-length term
      const std::array<int, 2> v{edges_[e][0], edges_[e][1]};
      LocalTerm<2> term(need);
      detail::addSquaredLengthTerm<2, 1, 1>([&p](const auto& q) { return detail::discreteShellsEdge(q, p.lengthWeight); },
                                            gather<2>(deformed, v), gather<2>(reference, v), kEdge, kEdge, need, 1.0, term);
      scatter<2>(term, v, need, pattern_, acc);
    }
#pragma omp for schedule(static) nowait
    for (Eigen::Index h = 0; h < numHingeTerms; ++h) {  // bending, weighted as in the header
      const std::array<int, 4> v{hinges_[h][0], hinges_[h][1], hinges_[h][2], hinges_[h][3]};
      LocalTerm<4> term(need);
      addHingeTerm(gather<4>(deformed, v), gather<4>(reference, v), hingeFactor, p.bendingWeight, need, term);
      scatter<4>(term, v, need, pattern_, acc);
    }
  }

  reduceAccumulators(accumulators, outputs, need, dofs, blocks);
}

void DiscreteShells::evaluate(const Eigen::VectorXd& reference, const Eigen::VectorXd& deformed,
                              const EnergyOutputs& outputs) const {
  assemble(reference, deformed, outputs, kMembrane | kBending);
}

double DiscreteShells::partsValue(const Eigen::VectorXd& reference, const Eigen::VectorXd& deformed, unsigned parts) const {
  double value = 0.0;
  EnergyOutputs outputs;
  outputs.value = &value;
  assemble(reference, deformed, outputs, parts);
  return value;
}
double DiscreteShells::membraneValue(const Eigen::VectorXd& reference, const Eigen::VectorXd& deformed) const {
  return partsValue(reference, deformed, kMembrane);
}
double DiscreteShells::bendingValue(const Eigen::VectorXd& reference, const Eigen::VectorXd& deformed) const {
  return partsValue(reference, deformed, kBending);
}

}  // namespace deformation_enrichment::shape_space
