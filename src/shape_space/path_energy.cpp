#include "deformation_enrichment/shape_space/path_energy.hpp"

#include <cmath>
#include <string>

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/numerics/sparse_cholesky.hpp"
#include "deformation_enrichment/shape_space/blas_threads.hpp"
#include "parallel_for.hpp"

namespace deformation_enrichment::shape_space {

double pathEnergy(const DeformationEnergy& energy, const std::vector<Eigen::VectorXd>& shapes, bool closed,
                  std::vector<Eigen::VectorXd>* gradients, bool endGradients) {
  double sum = 0.0;
  for (double segment : energy.pathSegments(shapes, closed, gradients, endGradients)) sum += segment;  // eq. 4
  return sum;
}

double pathLength(const DeformationEnergy& energy, const std::vector<Eigen::VectorXd>& shapes, bool closed) {
  double length = 0.0;
  for (double segment : energy.pathSegments(shapes, closed, nullptr, false)) length += std::sqrt(std::max(0.5 * segment, 0.0));
  return length;
}

void restHessians(const DeformationEnergy& energy, const std::vector<Eigen::VectorXd>& shapes,
                  std::vector<Eigen::SparseMatrix<double>>& hessians, bool ends) {
  const int count = int(shapes.size());
  hessians.resize(shapes.size());
  detail::parallelFor(count, energy.numVertices() >= detail::kParallelVertices, [&](int k) {
    if (!ends && (k == 0 || k == count - 1)) {
      hessians[size_t(k)] = Eigen::SparseMatrix<double>();
      return;
    }
    EnergyOutputs out;
    out.hessianDeformed = &hessians[size_t(k)];
    energy.evaluate(shapes[size_t(k)], shapes[size_t(k)], out);
  });
}

std::vector<Eigen::VectorXd> flowTangents(const DeformationEnergy& energy, const std::vector<Eigen::VectorXd>& shapes,
                                          bool closed) {
  std::vector<Eigen::VectorXd> gradients;
  pathEnergy(energy, shapes, closed, &gradients, false);
  std::vector<Eigen::SparseMatrix<double>> hessians;
  restHessians(energy, shapes, hessians, closed);
  return flowTangents(gradients, hessians, closed);
}

std::vector<Eigen::VectorXd> flowTangents(const std::vector<Eigen::VectorXd>& gradients,
                                          const std::vector<Eigen::SparseMatrix<double>>& restHessians, bool closed) {
  const int count = int(gradients.size());
  if (restHessians.size() != gradients.size())
    throw InvalidInputError("flow tangents: " + std::to_string(restHessians.size()) + " rest Hessians for " +
                            std::to_string(count) + " shapes");
  std::vector<Eigen::VectorXd> tangents(gradients.size());
  // Shapes in parallel only with a single-threaded BLAS (blas_threads.hpp): the supernodal factorisation's
  // threaded BLAS inside an OpenMP loop over shapes oversubscribes the cores (measured 2.4x slower on 2
  // cores). One factorisation per thread; each analyses the pattern once for all its shapes.
  const bool parallel = gradients.size() > 1 && gradients.front().size() >= 3 * detail::kParallelVertices &&
                        openBlasThreads() <= 1;
  std::vector<numerics::SparseCholesky> factorisations(parallel ? size_t(detail::maxThreads()) : 1);
  detail::parallelFor(count, parallel, [&](int k) {
    tangents[size_t(k)] = Eigen::VectorXd::Zero(gradients[size_t(k)].size());
    if (!closed && (k == 0 || k == count - 1)) return;
    numerics::SparseCholesky& cholesky = factorisations[parallel ? size_t(detail::threadIndex()) : 0];
    // eq. 9's metric d1d1 W(x, x) + d2d2 W(x, x) = 2 d2d2 W(x, x) (W(x, x) = 0 and its gradients vanish
    // there for every x, so d1d1 = -d1d2 = d2d2), and (2 H + 2 r I) v = -g / 2 is solved as
    // (H + r I) v = -g / 4. The ridge r removes the rigid null space.
    const Eigen::SparseMatrix<double>& h = restHessians[size_t(k)];
    if (h.rows() != gradients[size_t(k)].size() || h.cols() != h.rows())
      throw InvalidInputError("flow tangents: rest Hessian " + std::to_string(k) + " has the wrong size");
    const double ridge = 1e-8 * std::max(Eigen::VectorXd(h.diagonal()).cwiseAbs().mean(), 1e-300);
    const Eigen::VectorXd rhs = -0.25 * gradients[size_t(k)];
    if (cholesky.factorize(h, ridge)) {
      tangents[size_t(k)] = cholesky.solve(rhs);
      return;
    }
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt;  // semi-definite up to round-off: LDLT
    ldlt.setShift(ridge);
    ldlt.compute(h);
    if (ldlt.info() != Eigen::Success) throw NumericalError("flow tangents: rest Hessian factorisation failed");
    tangents[size_t(k)] = ldlt.solve(rhs);
  });
  return tangents;
}

}  // namespace deformation_enrichment::shape_space
