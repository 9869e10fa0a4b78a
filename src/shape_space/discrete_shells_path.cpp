// DiscreteShells::pathSegments: the terms W(a, b) + W(b, a) of eq. 4 ([Brandt16 eq. 4]) from per-shape element
// data. Every term of the shell energy is a function of per-element quantities of its two shapes (squared edge
// lengths, areas, edge lengths, dihedral angles, hinge weights); each shape's are computed once per call and
// shared by both directions of a segment and by both segments the shape belongs to, so a path of n shapes costs
// about n element passes instead of 4 (n - 1) (measured on the finger: a third of the time). The sum of both
// directions is a closed form in those quantities (the single-direction terms: discrete_shells.cpp,
// shell_elements.hpp):
//  - hyperelastic face ([Heeren12 eq. 8]): W(a, b) = mu P / (16 A_a) + lambda A_b^2 / (4 A_a) - kappa A_a (L_b - L_a)
//    - (mu + lambda / 4) A_a, kappa = mu / 2 + lambda / 4, L = log A^2, P = sum_m q_b,m c_a,m (c the cotangent
//    weights of the squared lengths q; P is symmetric in a and b);
//  - classic face and edge ([Grinspun03]): k (s_a - s_b)^2 / s_a with s the area or the length, so the sum is
//    k (s_a - s_b)^2 (1 / s_a + 1 / s_b);
//  - bending: (theta_b - theta_a)^2 w_a + (theta_a - theta_b)^2 w_b = (w_a + w_b) d^2, d the difference wrapped
//    into [-pi, pi] (as the single terms wrap it).
#include <array>
#include <cmath>
#include <exception>
#include <string>
#include <utility>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/shape_space/dihedral_angle.hpp"
#include "deformation_enrichment/shape_space/discrete_shells.hpp"
#include "shell_elements.hpp"
#include "shell_path_terms.hpp"

namespace deformation_enrichment::shape_space {

using detail::ShellPathTerms;

namespace {

std::array<double, 3> cotangentWeights(const std::array<double, 3>& q) {  // 8 A^2 cot(angle m), from squared lengths
  return {q[1] + q[2] - q[0], q[2] + q[0] - q[1], q[0] + q[1] - q[2]};
}

}  // namespace

void ShellPathTerms::prepare(const Eigen::VectorXd& x, int pathIndex, bool derivatives, Shape& out) const {
  shells_.DeformationEnergy::checkShape(x);  // size and finite entries
  const Eigen::Matrix3Xi& triangles = shells_.triangles_;
  out.faces.resize(size_t(triangles.cols()));
  out.faceDerivatives.resize(derivatives ? out.faces.size() : 0);
  for (Eigen::Index t = 0; t < triangles.cols(); ++t) {
    const Eigen::Vector3d x0 = x.segment<3>(3 * triangles(0, t)), x1 = x.segment<3>(3 * triangles(1, t)),
                          x2 = x.segment<3>(3 * triangles(2, t));
    const std::array<Eigen::Vector3d, 3> e{x1 - x2, x2 - x0, x0 - x1};
    const Eigen::Vector3d n = e[2].cross(-e[1]);
    const double doubleArea = n.norm();
    Face& face = out.faces[size_t(t)];
    face.q = {e[0].squaredNorm(), e[1].squaredNorm(), e[2].squaredNorm()};
    if (!(doubleArea > 2.0 * detail::kDegenerateAreaRatio * (face.q[0] + face.q[1] + face.q[2])))
      shells_.throwDegenerate(t, pathIndex == kReferenceShape ? std::string("a reference shape")
                                                              : "shape " + std::to_string(pathIndex) + " of the path",
                              0.5 * doubleArea);
    face.area = 0.5 * doubleArea;
    face.logAreaSquared = std::log(face.area * face.area);
    if (derivatives) out.faceDerivatives[size_t(t)] = {e, n / (2.0 * doubleArea)};
  }
  out.edges.resize(classic() ? shells_.edges_.size() : 0);
  for (size_t i = 0; i < out.edges.size(); ++i) {
    const Eigen::Vector3d edge = x.segment<3>(3 * shells_.edges_[i][0]) - x.segment<3>(3 * shells_.edges_[i][1]);
    const double length = edge.norm();
    out.edges[i] = {length, edge / length};
  }
  out.hinges.resize(bending() ? shells_.hinges_.size() : 0);
  out.hingeDerivatives.resize(derivatives ? out.hinges.size() : 0);
  const double c = classic() ? 3.0 : 1.0;  // as in discrete_shells.hpp
  for (size_t h = 0; h < out.hinges.size(); ++h) {
    const Eigen::Vector4i& v = shells_.hinges_[h];
    const std::array<Eigen::Vector3d, 4> xh{x.segment<3>(3 * v[0]), x.segment<3>(3 * v[1]), x.segment<3>(3 * v[2]),
                                            x.segment<3>(3 * v[3])};
    Hinge& hinge = out.hinges[h];
    if (derivatives) {
      HingeDerivatives& d = out.hingeDerivatives[h];
      hinge.theta = dihedralAngleAndGradient(xh[0], xh[1], xh[2], xh[3], d.theta);
      hinge.weight = detail::hingeWeightAndGradient(xh, c, &d.weight);
    } else {
      hinge.theta = dihedralAngle(xh[0], xh[1], xh[2], xh[3]);
      hinge.weight = detail::hingeWeightAndGradient(xh, c, nullptr);
    }
  }
}

double ShellPathTerms::segment(const Shape& a, const Shape& b, Eigen::VectorXd* ga, Eigen::VectorXd* gb) const {
  return faceTerms(a, b, ga, gb) + edgeTerms(a, b, ga, gb) + hingeTerms(a, b, ga, gb);
}

void ShellPathTerms::addFaceGradient(Eigen::Index t, const FaceDerivatives& face, const std::array<double, 3>& dq,
                                                double dArea, Eigen::VectorXd& g) const {
  for (int corner = 0; corner < 3; ++corner) {
    const int m1 = (corner + 1) % 3, m2 = (corner + 2) % 3;
    g.segment<3>(3 * shells_.triangles_(corner, t)) += 2.0 * (dq[size_t(m2)] * face.edges[size_t(m2)] - dq[size_t(m1)] * face.edges[size_t(m1)]) +
                                                       dArea * face.halfNormal.cross(-face.edges[size_t(corner)]);
  }
}

double ShellPathTerms::faceTerms(const Shape& a, const Shape& b, Eigen::VectorXd* ga, Eigen::VectorXd* gb) const {
  const DiscreteShellsOptions& p = shells_.parameters_;
  const double kappa = 0.5 * p.mu + 0.25 * p.lambda, constant = p.mu + 0.25 * p.lambda;
  double value = 0.0;
  for (size_t t = 0; t < a.faces.size(); ++t) {
    const Face &fa = a.faces[t], &fb = b.faces[t];
    const double inverseA = 1.0 / fa.area, inverseB = 1.0 / fb.area, difference = fa.area - fb.area;
    double dAreaA = 0.0, dAreaB = 0.0;  // d(term) / dA_a, d(term) / dA_b
    std::array<double, 3> dqA{0.0, 0.0, 0.0}, dqB{0.0, 0.0, 0.0};
    if (classic()) {  // k_A (A_a - A_b)^2 (1 / A_a + 1 / A_b)
      const double sum = inverseA + inverseB;
      value += p.areaWeight * difference * difference * sum;
      dAreaA = p.areaWeight * (2.0 * difference * sum - difference * difference * inverseA * inverseA);
      dAreaB = p.areaWeight * (-2.0 * difference * sum - difference * difference * inverseB * inverseB);
    } else {  // [Heeren12 eq. 8], both directions (header)
      const std::array<double, 3> ca = cotangentWeights(fa.q), cb = cotangentWeights(fb.q);
      const double pSum = fb.q[0] * ca[0] + fb.q[1] * ca[1] + fb.q[2] * ca[2];
      const double logDifference = fb.logAreaSquared - fa.logAreaSquared;
      value += p.mu / 16.0 * pSum * (inverseA + inverseB) +
               0.25 * p.lambda * (fb.area * fb.area * inverseA + fa.area * fa.area * inverseB) -
               kappa * difference * logDifference - constant * (fa.area + fb.area);
      if (!ga && !gb) continue;
      const double lengthFactor = p.mu / 16.0 * (inverseA + inverseB);
      for (int m = 0; m < 3; ++m) {
        dqA[size_t(m)] = lengthFactor * cb[size_t(m)];
        dqB[size_t(m)] = lengthFactor * ca[size_t(m)];
      }
      dAreaA = -p.mu / 16.0 * pSum * inverseA * inverseA +
               0.25 * p.lambda * (2.0 * fa.area * inverseB - fb.area * fb.area * inverseA * inverseA) - kappa * logDifference +
               2.0 * kappa * difference * inverseA - constant;
      dAreaB = -p.mu / 16.0 * pSum * inverseB * inverseB +
               0.25 * p.lambda * (2.0 * fb.area * inverseA - fa.area * fa.area * inverseB * inverseB) + kappa * logDifference -
               2.0 * kappa * difference * inverseB - constant;
    }
    if (ga) addFaceGradient(Eigen::Index(t), a.faceDerivatives[t], dqA, dAreaA, *ga);
    if (gb) addFaceGradient(Eigen::Index(t), b.faceDerivatives[t], dqB, dAreaB, *gb);
  }
  return value;
}

double ShellPathTerms::edgeTerms(const Shape& a, const Shape& b, Eigen::VectorXd* ga, Eigen::VectorXd* gb) const {
  const double k = shells_.parameters_.lengthWeight;
  double value = 0.0;
  for (size_t i = 0; i < a.edges.size(); ++i) {  // k_L (l_a - l_b)^2 (1 / l_a + 1 / l_b)
    const Edge &ea = a.edges[i], &eb = b.edges[i];
    const double inverseA = 1.0 / ea.length, inverseB = 1.0 / eb.length, difference = ea.length - eb.length;
    const double sum = inverseA + inverseB;
    value += k * difference * difference * sum;
    const Eigen::Vector2i& v = shells_.edges_[i];
    if (ga) {
      const Eigen::Vector3d dA = k * (2.0 * difference * sum - difference * difference * inverseA * inverseA) * ea.direction;
      ga->segment<3>(3 * v[0]) += dA;
      ga->segment<3>(3 * v[1]) -= dA;
    }
    if (gb) {
      const Eigen::Vector3d dB = k * (-2.0 * difference * sum - difference * difference * inverseB * inverseB) * eb.direction;
      gb->segment<3>(3 * v[0]) += dB;
      gb->segment<3>(3 * v[1]) -= dB;
    }
  }
  return value;
}

double ShellPathTerms::hingeTerms(const Shape& a, const Shape& b, Eigen::VectorXd* ga, Eigen::VectorXd* gb) const {
  const double k = shells_.parameters_.bendingWeight;
  double value = 0.0;
  for (size_t h = 0; h < a.hinges.size(); ++h) {  // k (w_a + w_b) d^2
    const Hinge &ha = a.hinges[h], &hb = b.hinges[h];
    const double d = detail::wrappedAngle(hb.theta - ha.theta);
    const double weight = k * (ha.weight + hb.weight);
    value += weight * d * d;
    const Eigen::Vector4i& v = shells_.hinges_[h];
    if (ga) {
      const Eigen::Matrix<double, 12, 1> dA = -2.0 * d * weight * a.hingeDerivatives[h].theta + (k * d * d) * a.hingeDerivatives[h].weight;
      for (int corner = 0; corner < 4; ++corner) ga->segment<3>(3 * v[corner]) += dA.segment<3>(3 * corner);
    }
    if (gb) {
      const Eigen::Matrix<double, 12, 1> dB = 2.0 * d * weight * b.hingeDerivatives[h].theta + (k * d * d) * b.hingeDerivatives[h].weight;
      for (int corner = 0; corner < 4; ++corner) gb->segment<3>(3 * v[corner]) += dB.segment<3>(3 * corner);
    }
  }
  return value;
}

std::vector<double> DiscreteShells::pathSegments(const std::vector<Eigen::VectorXd>& shapes, bool closed,
                                                 std::vector<Eigen::VectorXd>* gradients, bool endGradients) const {
  const int count = int(shapes.size());
  if (count < 2) throw InvalidInputError("path energy: a path needs at least 2 shapes, got " + std::to_string(count));
  const int segments = closed ? count : count - 1;
  std::vector<double> values(size_t(segments), 0.0);
  if (gradients) gradients->assign(shapes.size(), Eigen::VectorXd::Zero(3 * numVertices_));
  const auto wanted = [&](int k) { return gradients && (closed || endGradients || (k > 0 && k + 1 < count)); };
  const ShellPathTerms terms(*this);
  // Each thread runs a contiguous run of segments, sliding over its shapes (two shapes' data at a time). The
  // first shape of a run also ends the previous run: its share from this run goes to a buffer, added below.
  std::vector<Eigen::VectorXd> firstShapeGradients(static_cast<size_t>(threads_));
  std::vector<int> firstShapes(static_cast<size_t>(threads_), -1);
  std::exception_ptr error;
#pragma omp parallel num_threads(threads_) if (numVertices_ >= detail::kParallelVertices)
  {
#ifdef _OPENMP
    const int thread = omp_get_thread_num(), team = omp_get_num_threads();
#else
    const int thread = 0, team = 1;
#endif
    const int begin = segments * thread / team, end = segments * (thread + 1) / team;
    try {
      // Kept per thread across calls: freed, these megabytes went back to the OS and every call paid their
      // page faults again (measured on the finger: as much as the evaluations' arithmetic).
      thread_local ShellPathTerms::Shape current, next;
      if (begin < end) {
        terms.prepare(shapes[size_t(begin)], begin, wanted(begin), current);
        firstShapes[size_t(thread)] = begin;
        if (wanted(begin)) firstShapeGradients[size_t(thread)].setZero(3 * numVertices_);
      }
      for (int s = begin; s < end; ++s) {
        const int b = (s + 1) % count;
        terms.prepare(shapes[size_t(b)], b, wanted(b), next);
        Eigen::VectorXd* ga = !wanted(s) ? nullptr : s == begin ? &firstShapeGradients[size_t(thread)] : &(*gradients)[size_t(s)];
        values[size_t(s)] = terms.segment(current, next, ga, wanted(b) ? &(*gradients)[size_t(b)] : nullptr);
        std::swap(current, next);
      }
    } catch (...) {
#pragma omp critical
      error = std::current_exception();
    }
  }
  if (error) std::rethrow_exception(error);
  for (size_t t = 0; t < firstShapes.size(); ++t)
    if (firstShapes[t] >= 0 && wanted(firstShapes[t])) (*gradients)[size_t(firstShapes[t])] += firstShapeGradients[t];
  return values;
}

namespace detail {

const ShellReference* shellReferenceOf(const ReferenceData* data, const DiscreteShells& shells) {
  const auto* reference = dynamic_cast<const ShellReference*>(data);
  if (!reference) return nullptr;
  const DiscreteShellsOptions& p = shells.parameters();
  const ShellPathTerms::Shape& e = reference->elements;
  const bool fits = reference->membrane == p.membrane && e.faces.size() == size_t(shells.numTriangles()) &&
                    e.edges.size() == (p.membrane == MembraneModel::DiscreteShells ? shells.edges().size() : 0) &&
                    e.hinges.size() == (p.bendingWeight > 0.0 ? shells.hinges().size() : 0);
  return fits ? reference : nullptr;
}

}  // namespace detail

std::optional<double> DiscreteShells::pathEnergy(const std::vector<const ReferenceData*>& data, bool closed) const {
  const int count = int(data.size());
  if (count < 2) throw InvalidInputError("path energy: a path needs at least 2 shapes, got " + std::to_string(count));
  std::vector<const ShellPathTerms::Shape*> shapes(data.size(), nullptr);
  for (size_t i = 0; i < data.size(); ++i) {
    const detail::ShellReference* reference = detail::shellReferenceOf(data[i], *this);
    if (!reference) throw InvalidInputError("DiscreteShells: path data " + std::to_string(i) + " is not of this energy");
    shapes[i] = &reference->elements;
  }
  const int segments = closed ? count : count - 1;
  std::vector<double> values(size_t(segments), 0.0);  // summed in path order: the same sum for any thread count
  const ShellPathTerms terms(*this);
#pragma omp parallel for num_threads(threads_) if (numVertices_ >= detail::kParallelVertices)
  for (int s = 0; s < segments; ++s) values[size_t(s)] = terms.segment(*shapes[size_t(s)], *shapes[size_t((s + 1) % count)], nullptr, nullptr);
  double sum = 0.0;
  for (double value : values) sum += value;
  return sum;
}

}  // namespace deformation_enrichment::shape_space
