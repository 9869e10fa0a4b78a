#include "deformation_enrichment/shape_space/path_energy.hpp"

#include <cmath>
#include <exception>
#include <string>

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include "deformation_enrichment/error.hpp"
#include "sparse_cholesky.hpp"

namespace deformation_enrichment::shape_space {
namespace {

int wrap(int i, int count) { return ((i % count) + count) % count; }

// The terms of eq. 4: segment s joins x_s and x_s+1 (mod count if closed).
int segmentCount(int count, bool closed) { return closed ? count : count - 1; }

// Per segment W(a, b) + W(b, a) and, with gradients, the derivatives summed per shape.
std::vector<double> segmentEnergies(const DeformationEnergy& energy, const std::vector<Eigen::VectorXd>& shapes,
                                    bool closed, std::vector<Eigen::VectorXd>* gradients) {
  const int count = int(shapes.size());
  if (count < 2) throw InvalidInputError("path energy: a path needs at least 2 shapes, got " + std::to_string(count));
  const int passes = 2 * segmentCount(count, closed);  // pass 2s: W(x_s, x_s+1); pass 2s+1: W(x_s+1, x_s)
  std::vector<double> values(size_t(passes), 0.0);
  std::vector<Eigen::VectorXd> gradReference(gradients ? size_t(passes) : 0), gradDeformed(gradients ? size_t(passes) : 0);
  const auto shapesOf = [&](int p) {
    const int a = p / 2, b = wrap(a + 1, count);
    return p % 2 == 0 ? std::pair<int, int>{a, b} : std::pair<int, int>{b, a};
  };
  std::exception_ptr error;
#pragma omp parallel for schedule(dynamic) if (energy.numVertices() >= 1000)
  for (int p = 0; p < passes; ++p) {
    try {
      const auto [reference, deformed] = shapesOf(p);
      EnergyOutputs out;
      out.value = &values[size_t(p)];
      if (gradients) {
        out.gradientReference = &gradReference[size_t(p)];
        out.gradientDeformed = &gradDeformed[size_t(p)];
      }
      energy.evaluate(shapes[size_t(reference)], shapes[size_t(deformed)], out);
    } catch (...) {
#pragma omp critical
      error = std::current_exception();
    }
  }
  if (error) std::rethrow_exception(error);
  if (gradients) {
    gradients->assign(shapes.size(), Eigen::VectorXd::Zero(shapes.front().size()));
    for (int p = 0; p < passes; ++p) {
      const auto [reference, deformed] = shapesOf(p);
      (*gradients)[size_t(reference)] += gradReference[size_t(p)];
      (*gradients)[size_t(deformed)] += gradDeformed[size_t(p)];
    }
  }
  std::vector<double> segments(size_t(passes / 2));
  for (size_t s = 0; s < segments.size(); ++s) segments[s] = values[2 * s] + values[2 * s + 1];
  return segments;
}

}  // namespace

double pathEnergy(const DeformationEnergy& energy, const std::vector<Eigen::VectorXd>& shapes, bool closed,
                  std::vector<Eigen::VectorXd>* gradients) {
  double sum = 0.0;
  for (double segment : segmentEnergies(energy, shapes, closed, gradients)) sum += segment;  // eq. 4
  return sum;
}

double pathLength(const DeformationEnergy& energy, const std::vector<Eigen::VectorXd>& shapes, bool closed) {
  double length = 0.0;
  for (double segment : segmentEnergies(energy, shapes, closed, nullptr)) length += std::sqrt(std::max(0.5 * segment, 0.0));
  return length;
}

std::vector<Eigen::VectorXd> flowTangents(const DeformationEnergy& energy, const std::vector<Eigen::VectorXd>& shapes,
                                          bool closed) {
  std::vector<Eigen::VectorXd> gradients;
  pathEnergy(energy, shapes, closed, &gradients);
  const int count = int(shapes.size());
  std::vector<Eigen::VectorXd> tangents(shapes.size());
  detail::SparseCholesky cholesky;  // one symbolic analysis for all shapes (one pattern)
  // Shape by shape: the supernodal factorisation runs a threaded BLAS, which oversubscribes the cores
  // inside an OpenMP loop over shapes (measured 2.4x slower on 2 cores).
  for (int k = 0; k < count; ++k) {
    tangents[size_t(k)] = Eigen::VectorXd::Zero(shapes[size_t(k)].size());
    if (!closed && (k == 0 || k == count - 1)) continue;
    // eq. 9's metric d1d1 W(x, x) + d2d2 W(x, x) = 2 d2d2 W(x, x) (W(x, x) = 0 and its gradients vanish
    // there for every x, so d1d1 = -d1d2 = d2d2): one d2d2 pass. The ridge removes the rigid null space.
    const Eigen::SparseMatrix<double> h = 2.0 * energy.hessianDeformed(shapes[size_t(k)], shapes[size_t(k)]);
    const double ridge = 1e-8 * std::max(Eigen::VectorXd(h.diagonal()).cwiseAbs().mean(), 1e-300);
    const Eigen::VectorXd rhs = -0.5 * gradients[size_t(k)];
    if (cholesky.factorize(h, ridge)) {
      tangents[size_t(k)] = cholesky.solve(rhs);
      continue;
    }
    Eigen::SparseMatrix<double> shifted = h;  // semi-definite up to round-off: LDLT
    for (Eigen::Index i = 0; i < shifted.rows(); ++i) shifted.coeffRef(i, i) += ridge;
    const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(shifted);
    if (ldlt.info() != Eigen::Success) throw NumericalError("flow tangents: rest Hessian factorisation failed");
    tangents[size_t(k)] = ldlt.solve(rhs);
  }
  return tangents;
}

}  // namespace deformation_enrichment::shape_space
