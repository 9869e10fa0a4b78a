// DiscreteShells::weightedReferences: sum_i w_i W[x_i, y] (the eq. 10 objective) in one pass over the mesh.
// Every term of the shell energy is, for a fixed deformed element, linear in functions of the reference
// element alone, so the weighted examples aggregate into per-element coefficients computed once:
//  - hyperelastic face ([Heeren12 eq. 8]): A_bar (mu/2 tr G + lambda/4 det G - (mu + lambda/2) log(A/A_bar)
//    - mu - lambda/4) with tr G = sum_m q_m c_m(q_bar) / (8 A_bar^2), det G = A^2 / A_bar^2, so the sum is
//    sum_m C_m q_m + D A^2 - S log A + const;
//  - classic edge / area terms: k (1 - l/l_bar)^2 l_bar = k (l - l_bar)^2 / l_bar, so the sum is
//    k a (l - l_star)^2 + k sum_i w_i (l_bar_i - l_star)^2 / l_bar_i with a = sum_i w_i / l_bar_i and
//    l_star = (sum_i w_i) / a (no cancellation: for one example this is the original form);
//  - bending: sum_i w_i omega_i (theta - theta_bar_i)^2 = Omega (theta - theta_star)^2 + const with
//    Omega = sum_i w_i omega_i and theta_star the omega-weighted mean of theta_bar_i. The energy takes each
//    difference modulo 2 pi, so this holds only where theta (shifted by 2 pi k to lie nearest theta_star)
//    is within pi of every theta_bar_i; elsewhere (references whose angles spread widely, as on noisy
//    hinges: measured 117 of 1000 hinges of a sydney.md2 clip with 0.4 % noise, where the aggregated value
//    was 24 % off) the hinge sums its terms one by one.
// The evaluation then costs one deformed-only pass instead of one full pass per example.
#include <array>
#include <cmath>
#include <string>

#include <Eigen/Geometry>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/shape_space/dihedral_angle.hpp"
#include "deformation_enrichment/shape_space/discrete_shells.hpp"
#include "shell_elements.hpp"
#include "shell_path_terms.hpp"

namespace deformation_enrichment::shape_space {
namespace {

using detail::kDegenerateAreaRatio;

template <int NV, class Index>
std::array<Eigen::Vector3d, NV> gatherCorners(const Eigen::VectorXd& shape, const Index& vertices) {
  std::array<Eigen::Vector3d, NV> x;
  for (int a = 0; a < NV; ++a) x[size_t(a)] = shape.segment<3>(3 * vertices[a]);
  return x;
}

std::array<double, 3> squaredLengths(const std::array<Eigen::Vector3d, 3>& x) {
  return {(x[1] - x[2]).squaredNorm(), (x[2] - x[0]).squaredNorm(), (x[0] - x[1]).squaredNorm()};
}

bool degenerate(const std::array<Eigen::Vector3d, 3>& x) {
  const double doubleArea = (x[1] - x[0]).cross(x[2] - x[0]).norm();
  const std::array<double, 3> q = squaredLengths(x);
  return !(doubleArea > 2.0 * kDegenerateAreaRatio * (q[0] + q[1] + q[2]));
}

using detail::ShellReference;

ShellReference shellReference(const DiscreteShells& shells, const Eigen::VectorXd& ref) {
  ShellReference r;
  r.membrane = shells.parameters().membrane;
  detail::ShellPathTerms(shells).prepare(ref, detail::ShellPathTerms::kReferenceShape, false, r.elements);
  return r;
}

class ShellWeightedReferences final : public WeightedReferenceEnergy {
public:
  // data[i] (if given and not null) is shells.referenceData(*references[i]).
  ShellWeightedReferences(const DiscreteShells& shells, const std::vector<double>& weights,
                          const std::vector<const Eigen::VectorXd*>& references, const std::vector<const ShellReference*>& data)
      : shells_(shells), hyperelastic_(shells.parameters().membrane == MembraneModel::Hyperelastic) {
    const DiscreteShellsOptions& p = shells.parameters();
    const Eigen::Index numTriangles = shells.numTriangles();
    faces_.assign(size_t(numTriangles), {});
    if (!hyperelastic_) edges_.assign(shells.edges().size(), {});
    hinges_.assign(shells.hinges().size(), {});
    std::vector<double> thetaFirst(hinges_.size(), 0.0), omegaTheta(hinges_.size(), 0.0), omegaTheta2(hinges_.size(), 0.0);
    std::vector<double> thetaMin(hinges_.size(), 0.0), thetaMax(hinges_.size(), 0.0);
    std::vector<const ShellReference*> used(references.size(), nullptr);  // of the references with weight
    std::vector<ShellReference> computed;
    computed.reserve(references.size());
    for (size_t i = 0; i < references.size(); ++i) {
      if (weights[i] == 0.0) continue;
      used[i] = data.empty() ? nullptr : data[i];
      if (!used[i]) used[i] = &computed.emplace_back(shellReference(shells, *references[i]));
    }
    bool first = true;
    for (size_t i = 0; i < references.size(); ++i) {
      const double w = weights[i];
      if (w == 0.0) continue;
      const ShellReference& ref = *used[i];
      for (Eigen::Index t = 0; t < numTriangles; ++t) {
        const std::array<double, 3>& r = ref.elements.faces[size_t(t)].q;
        const double area = ref.elements.faces[size_t(t)].area;
        Face& f = faces_[size_t(t)];
        if (hyperelastic_) {
          const double c = 0.5 * p.mu / (8.0 * area);
          f.linear[0] += w * c * (r[1] + r[2] - r[0]);
          f.linear[1] += w * c * (r[2] + r[0] - r[1]);
          f.linear[2] += w * c * (r[0] + r[1] - r[2]);
          f.quadratic += w * 0.25 * p.lambda / area;
          // -S log A is evaluated as -S log(A / scale) (scale: the first example's area) so that the large
          // log terms cancel per face, not across the mesh.
          if (first) f.scale = area;
          f.logarithmic += w * area * (p.mu + 0.5 * p.lambda);
          f.constant += w * area * ((p.mu + 0.5 * p.lambda) * std::log(area / f.scale) - p.mu - 0.25 * p.lambda);
        } else {  // k_A (A - A_bar)^2 / A_bar: sum w and sum w / A_bar here, the rest below
          f.linear[0] += w;
          f.quadratic += w / area;
        }
      }
      if (!hyperelastic_) {
        for (size_t e = 0; e < edges_.size(); ++e) {  // k_L (l - l_bar)^2 / l_bar, as the faces
          edges_[e].linear += w;
          edges_[e].quadratic += w / ref.elements.edges[e].length;
        }
      }
      if (p.bendingWeight > 0.0) {
        for (size_t h = 0; h < hinges_.size(); ++h) {
          double theta = ref.elements.hinges[h].theta;
          // Unwrapped against the first example so that hinges near +-pi aggregate consistently.
          if (first) thetaFirst[h] = theta;
          else theta = thetaFirst[h] + detail::wrappedAngle(theta - thetaFirst[h]);
          const double omega = w * p.bendingWeight * ref.elements.hinges[h].weight;
          hinges_[h].omega += omega;
          omegaTheta[h] += omega * theta;
          omegaTheta2[h] += omega * (theta - thetaFirst[h]) * (theta - thetaFirst[h]);  // shifted: no cancellation
          thetaMin[h] = first ? theta : std::min(thetaMin[h], theta);
          thetaMax[h] = first ? theta : std::max(thetaMax[h], theta);
          hingeTerms_.push_back({omega, theta});  // reference-major: term (i, h) at i * hinges + h
        }
      }
      first = false;
      ++references_;
    }
    if (!hyperelastic_) classicTargets(weights, used);
    for (size_t h = 0; h < hinges_.size(); ++h) {
      Hinge& hinge = hinges_[h];
      if (!(hinge.omega > 0.0)) continue;
      hinge.theta = omegaTheta[h] / hinge.omega;
      const double shift = hinge.theta - thetaFirst[h];
      hinge.constant = omegaTheta2[h] - hinge.omega * shift * shift;  // sum_i omega_i (theta_bar_i - theta_star)^2
      hinge.lowest = thetaMax[h] - M_PI - hinge.theta;
      hinge.highest = thetaMin[h] + M_PI - hinge.theta;
    }
  }

  double evaluate(const Eigen::VectorXd& y, Eigen::VectorXd* gradient) const override {
    checkDeformed(y);
    if (gradient) gradient->setZero(y.size());
    double value = constant_;
    // Closed forms in the deformed edge vectors (no jets: this pass runs once per solver evaluation).
    // A^2 = |n|^2 / 4 with n = (x1 - x0) x (x2 - x0), and d(A^2)/dx_a = n x (x_c - x_b) / 2 for (a, b, c)
    // cyclic, so every face term is a function of q_m = |e_m|^2 and A^2 alone.
    for (Eigen::Index t = 0; t < shells_.numTriangles(); ++t) {
      const Eigen::Vector3i v = shells_.triangles().col(t);
      const auto x = gatherCorners<3>(y, v);
      const std::array<Eigen::Vector3d, 3> e{x[1] - x[2], x[2] - x[0], x[0] - x[1]};  // edge m opposite corner m
      const Eigen::Vector3d normal = e[2].cross(-e[1]);                                 // (x1 - x0) x (x2 - x0)
      const double q[3] = {e[0].squaredNorm(), e[1].squaredNorm(), e[2].squaredNorm()};
      // Squared forms: the hyperelastic terms need no square root (|n| > 2 r sum q as |n|^2 > (2 r sum q)^2).
      const double doubleAreaSquared = normal.squaredNorm(), bound = 2.0 * kDegenerateAreaRatio * (q[0] + q[1] + q[2]);
      if (!(doubleAreaSquared > bound * bound))
        throw InvalidInputError("DiscreteShells: triangle " + std::to_string(t) + " of the deformed shape is degenerate");
      const Face& f = faces_[size_t(t)];
      const double areaSquared = 0.25 * doubleAreaSquared;
      double dArea2 = 0.0;  // d value / d(A^2)
      if (hyperelastic_) {  // sum_m C_m q_m + D A^2 - S/2 log(A^2 / scale^2) + const (header)
        value += f.linear[0] * q[0] + f.linear[1] * q[1] + f.linear[2] * q[2] + f.quadratic * areaSquared -
                 0.5 * f.logarithmic * std::log(areaSquared / (f.scale * f.scale)) + f.constant;
        dArea2 = f.quadratic - 0.5 * f.logarithmic / areaSquared;
      } else {  // k_A a (A - A_star)^2 + const
        const double area = std::sqrt(areaSquared), excess = area - f.linear[0];
        value += f.quadratic * excess * excess + f.constant;
        dArea2 = f.quadratic * excess / area;  // d/d(A^2) of (A - A_star)^2 = (A - A_star) / A
      }
      if (!gradient) continue;
      for (int a = 0; a < 3; ++a) {
        // e_m = x_b - x_c for the corners b = m + 1, c = m + 2: dq_m/dx_b = 2 e_m = -dq_m/dx_c
        Eigen::Vector3d g = (0.5 * dArea2) * normal.cross(-e[size_t(a)]);  // n x (x_c - x_b) / 2 per unit d(A^2)
        if (hyperelastic_) g += 2.0 * (f.linear[size_t((a + 2) % 3)] * e[size_t((a + 2) % 3)] - f.linear[size_t((a + 1) % 3)] * e[size_t((a + 1) % 3)]);
        gradient->segment<3>(3 * v[a]) += g;
      }
    }
    for (size_t e = 0; e < edges_.size(); ++e) {  // k_L a (l - l_star)^2
      const Eigen::Vector2i v = shells_.edges()[e];
      const Edge& coefficients = edges_[e];
      const Eigen::Vector3d edge = y.segment<3>(3 * v[0]) - y.segment<3>(3 * v[1]);
      const double length = edge.norm(), excess = length - coefficients.linear;
      value += coefficients.quadratic * excess * excess;
      if (!gradient) continue;
      const Eigen::Vector3d g = (2.0 * coefficients.quadratic * excess / length) * edge;
      gradient->segment<3>(3 * v[0]) += g;
      gradient->segment<3>(3 * v[1]) -= g;
    }
    Eigen::Matrix<double, 12, 1> dTheta;
    for (size_t h = 0; h < hinges_.size(); ++h) {
      const Hinge& hinge = hinges_[h];
      if (!(hinge.omega > 0.0)) continue;
      const Eigen::Vector4i v = shells_.hinges()[h];
      const auto x = gatherCorners<4>(y, v);
      const double theta = gradient ? dihedralAngleAndGradient(x[0], x[1], x[2], x[3], dTheta)
                                    : dihedralAngle(x[0], x[1], x[2], x[3]);
      const HingeValue b = hingeValue(h, theta);
      value += b.value;
      const double slope = b.slope;
      if (gradient)
        for (int a = 0; a < 4; ++a) gradient->segment<3>(3 * v[a]) += slope * dTheta.segment<3>(3 * a);
    }
    return value;
  }

  Eigen::SparseMatrix<double> hessian(const Eigen::VectorXd& y) const override {
    checkDeformed(y);
    Eigen::SparseMatrix<double> h = shells_.hessianPattern().zeros;
    double* const values = h.valuePtr();
    static constexpr std::array<detail::LocalEdge, 3> kTriangleEdges{{{1, 2}, {2, 0}, {0, 1}}};  // edge m opposite corner m
    static constexpr std::array<detail::LocalEdge, 1> kEdge{{{0, 1}}};
    static constexpr std::array<detail::LocalEdge, 0> kNone{};
    for (Eigen::Index t = 0; t < shells_.numTriangles(); ++t) {
      const std::array<int, 3> v{shells_.triangles()(0, t), shells_.triangles()(1, t), shells_.triangles()(2, t)};
      const auto x = gatherCorners<3>(y, v);
      if (degenerate(x)) throw InvalidInputError("DiscreteShells: triangle " + std::to_string(t) + " of the deformed shape is degenerate");
      const Face& f = faces_[size_t(t)];
      detail::LocalTerm<3> term(detail::kHessianDeformed);
      if (hyperelastic_) {  // sum_m C_m q_m + D A^2 - S / 2 log(A^2) + const, in closed form
        detail::addFaceHessian(x, f.linear, f.quadratic, -0.5 * f.logarithmic, term.hessianDeformed);
      } else {  // k_A a (A - A_star)^2: jets in the 3 deformed squared lengths
        detail::addSquaredLengthTerm<3, 3, 0>(
            [&f](const auto& q) {
              const auto area = detail::triangleArea(q[0], q[1], q[2]);
              return f.quadratic * (area - f.linear[0]) * (area - f.linear[0]);
            },
            x, x, kTriangleEdges, kNone, detail::kHessianDeformed, 1.0, term);
      }
      detail::scatterHessian<3>(term.hessianDeformed, v, shells_.hessianPattern(), values);
    }
    for (size_t e = 0; e < edges_.size(); ++e) {
      const std::array<int, 2> v{shells_.edges()[e][0], shells_.edges()[e][1]};
      const Edge& c = edges_[e];
      detail::LocalTerm<2> term(detail::kHessianDeformed);
      detail::addSquaredLengthTerm<2, 1, 0>([&c](const auto& q) { return c.quadratic * (sqrt(q[0]) - c.linear) * (sqrt(q[0]) - c.linear); },
                                            gatherCorners<2>(y, v), gatherCorners<2>(y, v), kEdge, kNone,
                                            detail::kHessianDeformed, 1.0, term);
      detail::scatterHessian<2>(term.hessianDeformed, v, shells_.hessianPattern(), values);
    }
    for (size_t k = 0; k < hinges_.size(); ++k) {  // curvature * grad grad^T + slope * Hessian of theta
      if (!(hinges_[k].omega > 0.0)) continue;
      const std::array<int, 4> v{shells_.hinges()[k][0], shells_.hinges()[k][1], shells_.hinges()[k][2], shells_.hinges()[k][3]};
      const auto x = gatherCorners<4>(y, v);
      const HingeAngle theta = dihedralAngleDerivatives(x[0], x[1], x[2], x[3], true);
      const HingeValue b = hingeValue(k, theta.theta);
      const Eigen::Matrix<double, 12, 12> local = b.curvature * theta.gradient * theta.gradient.transpose() + b.slope * theta.hessian;
      detail::scatterHessian<4>(local, v, shells_.hessianPattern(), values);
    }
    return h;
  }

private:
  struct HingeValue {
    double value = 0.0, slope = 0.0, curvature = 0.0;  // the hinge's term and its first two derivatives in theta
  };

  // The aggregated form where it holds, else the terms one by one (header).
  HingeValue hingeValue(size_t h, double theta) const {
    const Hinge& hinge = hinges_[h];
    HingeValue b;
    const double d = detail::wrappedAngle(theta - hinge.theta);
    if (d >= hinge.lowest && d <= hinge.highest) {
      b.value = hinge.omega * d * d + hinge.constant;
      b.slope = 2.0 * hinge.omega * d;
      b.curvature = 2.0 * hinge.omega;
      return b;
    }
    for (size_t i = 0; i < references_; ++i) {
      const HingeTerm& term = hingeTerms_[i * hinges_.size() + h];
      const double di = detail::wrappedAngle(theta - term.theta);
      b.value += term.omega * di * di;
      b.slope += 2.0 * term.omega * di;
      b.curvature += 2.0 * term.omega;
    }
    return b;
  }

  void checkDeformed(const Eigen::VectorXd& y) const {
    const Eigen::Index n = 3 * shells_.numVertices();
    if (y.size() != n)
      throw InvalidInputError("DiscreteShells: deformed shape has " + std::to_string(y.size()) + " entries, expected " +
                              std::to_string(n));
    if (!y.allFinite()) throw InvalidInputError("DiscreteShells: deformed shape is not finite");
  }

  // Classic membrane: turns the sums (sum w, sum w / x_bar) into (x_star, k a) and adds
  // k sum_i w_i (x_bar_i - x_star)^2 / x_bar_i to the constants (a second pass over the examples).
  void classicTargets(const std::vector<double>& weights, const std::vector<const ShellReference*>& references) {
    const DiscreteShellsOptions& p = shells_.parameters();
    for (Face& f : faces_) {
      f.linear[0] = f.quadratic > 0.0 ? f.linear[0] / f.quadratic : 0.0;
      f.quadratic *= p.areaWeight;
    }
    for (Edge& e : edges_) {
      e.linear = e.quadratic > 0.0 ? e.linear / e.quadratic : 0.0;
      e.quadratic *= p.lengthWeight;
    }
    for (size_t i = 0; i < references.size(); ++i) {
      const double w = weights[i];
      if (w == 0.0) continue;
      for (Eigen::Index t = 0; t < shells_.numTriangles(); ++t) {
        const double area = references[i]->elements.faces[size_t(t)].area, excess = area - faces_[size_t(t)].linear[0];
        faces_[size_t(t)].constant += w * p.areaWeight * excess * excess / area;
      }
      for (size_t e = 0; e < edges_.size(); ++e) {
        const double length = references[i]->elements.edges[e].length, excess = length - edges_[e].linear;
        constant_ += w * p.lengthWeight * excess * excess / length;
      }
    }
  }

  struct Face {
    std::array<double, 3> linear{0.0, 0.0, 0.0};  // hyperelastic: C_m; classic: [0] the target area A_star
    double quadratic = 0.0;                       // of A^2 (hyperelastic) or (A - A_star)^2 (classic)
    double logarithmic = 0.0;                     // of -log(A / scale) (hyperelastic)
    double scale = 1.0;
    double constant = 0.0;
  };
  struct Edge {
    double linear = 0.0, quadratic = 0.0;  // l_star and the coefficient of (l - l_star)^2
  };
  struct Hinge {
    double omega = 0.0, theta = 0.0;  // bendingWeight-scaled Omega and theta_star
    double constant = 0.0;            // sum_i omega_i (theta_bar_i - theta_star)^2
    double lowest = 0.0, highest = 0.0;  // the range of theta - theta_star (mod 2 pi) where that form holds
  };
  struct HingeTerm {
    double omega, theta;  // one reference's weight and (unwrapped) angle
  };

  const DiscreteShells& shells_;
  bool hyperelastic_;
  std::vector<Face> faces_;
  std::vector<Edge> edges_;
  std::vector<Hinge> hinges_;
  std::vector<HingeTerm> hingeTerms_;
  size_t references_ = 0;  // with nonzero weight (and so terms in hingeTerms_ if bending is on)
  double constant_ = 0.0;
};

}  // namespace

std::unique_ptr<WeightedReferenceEnergy> DiscreteShells::weightedReferences(
    const std::vector<double>& weights, const std::vector<const Eigen::VectorXd*>& references,
    const std::vector<const ReferenceData*>& data) const {
  if (weights.size() != references.size())
    throw InvalidInputError("DiscreteShells: " + std::to_string(weights.size()) + " weights for " +
                            std::to_string(references.size()) + " references");
  if (!data.empty() && data.size() != references.size())
    throw InvalidInputError("DiscreteShells: " + std::to_string(data.size()) + " reference data for " +
                            std::to_string(references.size()) + " references");
  for (size_t i = 0; i < references.size(); ++i) {
    if (!(std::isfinite(weights[i]) && weights[i] >= 0.0))
      throw InvalidInputError("DiscreteShells: weight " + std::to_string(i) + " is negative or not finite");
    if (references[i] == nullptr || references[i]->size() != 3 * numVertices_)
      throw InvalidInputError("DiscreteShells: reference " + std::to_string(i) + " has the wrong size");
    if (!references[i]->allFinite()) throw InvalidInputError("DiscreteShells: reference " + std::to_string(i) + " is not finite");
  }
  std::vector<const ShellReference*> shellData(data.size(), nullptr);
  for (size_t i = 0; i < data.size(); ++i) {
    shellData[i] = detail::shellReferenceOf(data[i], *this);
    if (data[i] && !shellData[i])
      throw InvalidInputError("DiscreteShells: reference data " + std::to_string(i) + " is not of this energy");
  }
  return std::make_unique<ShellWeightedReferences>(*this, weights, references, shellData);
}

std::shared_ptr<const ReferenceData> DiscreteShells::referenceData(const Eigen::VectorXd& shape) const {
  return std::make_shared<const ShellReference>(shellReference(*this, shape));
}

}  // namespace deformation_enrichment::shape_space
