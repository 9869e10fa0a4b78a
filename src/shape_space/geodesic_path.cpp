#include "deformation_enrichment/shape_space/geodesic_path.hpp"

#include <cmath>
#include <limits>
#include <string>

#include <Eigen/SparseCore>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/numerics/damped_newton.hpp"
#include "deformation_enrichment/shape_space/path_energy.hpp"
#include "parallel_for.hpp"

namespace deformation_enrichment::shape_space {
namespace {

void checkPath(const DeformationEnergy& energy, const std::vector<Eigen::VectorXd>& shapes, const char* what) {
  if (shapes.size() < 3)
    throw InvalidInputError(std::string(what) + ": a path needs at least 3 shapes, got " + std::to_string(shapes.size()));
  for (size_t k = 0; k < shapes.size(); ++k) {
    if (shapes[k].size() != 3 * energy.numVertices())
      throw InvalidInputError(std::string(what) + ": shape " + std::to_string(k) + " has the wrong size");
    if (!shapes[k].allFinite()) throw InvalidInputError(std::string(what) + ": shape " + std::to_string(k) + " is not finite");
  }
}

// The 2 (K - 1) energy passes of eq. 4 (W(x_s, x_s+1) and W(x_s+1, x_s) for every segment s).
struct Pass {
  int reference, deformed;
};
std::vector<Pass> passes(int count) {
  std::vector<Pass> out;
  for (int s = 0; s + 1 < count; ++s) {
    out.push_back({s, s + 1});
    out.push_back({s + 1, s});
  }
  return out;
}

// eq. 4 as an objective for dampedNewton: +infinity where a trial collapsed a triangle (the energy rejects it).
double pathEnergyOrInfinity(const DeformationEnergy& energy, const std::vector<Eigen::VectorXd>& shapes,
                            std::vector<Eigen::VectorXd>* gradients) {
  try {
    return pathEnergy(energy, shapes, false, gradients, false);  // the ends are fixed
  } catch (const InvalidInputError&) {
    return std::numeric_limits<double>::infinity();
  }
}

// A model of the reduced Hessian B^T d2(eq. 4) B (dense: a few hundred unknowns), projected inside the
// parallel loop. It takes each segment's W(x_r, x_s) + W(x_s, x_r) as the quadratic
// 1/2 (x_s - x_r)^T (H_r + H_s) (x_s - x_r) with the rest Hessians H_k = d2d2 W(x_k, x_k) (exact when x_r = x_s:
// there d1d1 W = d2d2 W = -d1d2 W), so one Hessian per shape gives all blocks, and at rest its angle terms
// vanish ([Brandt16 §6] warm-starts BFGS from rest Hessians too). Measured on the finger: 40 % of the
// per-term model's cost (d2d2 W(x_r, x_s) per term) for 31 instead of 26 iterations, the same length.
Eigen::MatrixXd reducedHessianModel(const std::vector<Eigen::SparseMatrix<double>>& restHessians, const Eigen::MatrixXd& basis,
                                    Eigen::Index numVertices) {
  const int count = int(restHessians.size());
  const Eigen::Index d = basis.cols();
  std::vector<Eigen::MatrixXd> rest(restHessians.size());
  detail::parallelFor(count, numVertices >= detail::kParallelVertices, [&](int k) { rest[size_t(k)] = basis.transpose() * (restHessians[size_t(k)] * basis); });
  Eigen::MatrixXd model = Eigen::MatrixXd::Zero(d * (count - 2), d * (count - 2));
  const auto inner = [&](int k) { return k > 0 && k + 1 < count; };
  for (int r = 0; r + 1 < count; ++r) {
    const int s = r + 1;
    const Eigen::MatrixXd block = rest[size_t(r)] + rest[size_t(s)];
    if (inner(r)) model.block(d * (r - 1), d * (r - 1), d, d) += block;
    if (inner(s)) model.block(d * (s - 1), d * (s - 1), d, d) += block;
    if (inner(r) && inner(s)) {
      model.block(d * (r - 1), d * (s - 1), d, d) -= block;
      model.block(d * (s - 1), d * (r - 1), d, d) -= block;
    }
  }
  return 0.5 * (model + model.transpose());
}

// The exact Hessian of eq. 4 over the inner shapes (lower triangle) from the per-pass blocks.
Eigen::SparseMatrix<double> pathHessian(const DeformationEnergy& energy, const std::vector<Eigen::VectorXd>& shapes) {
  const int count = int(shapes.size());
  const Eigen::Index n = shapes.front().size(), unknowns = n * (count - 2);
  const std::vector<Pass> all = passes(count);
  std::vector<Eigen::SparseMatrix<double>> hd(all.size()), hm(all.size()), hr(all.size());
  detail::parallelFor(int(all.size()), energy.numVertices() >= detail::kParallelVertices, [&](int p) {
    EnergyOutputs out;
    out.hessianDeformed = &hd[size_t(p)];
    out.hessianMixed = &hm[size_t(p)];
    out.hessianReference = &hr[size_t(p)];
    energy.evaluate(shapes[size_t(all[size_t(p)].reference)], shapes[size_t(all[size_t(p)].deformed)], out);
  });
  std::vector<Eigen::Triplet<double>> triplets;
  const auto add = [&](const Eigen::SparseMatrix<double>& block, int rowShape, int colShape, bool transpose) {
    if (rowShape == 0 || rowShape == count - 1 || colShape == 0 || colShape == count - 1) return;
    const Eigen::Index r0 = n * (rowShape - 1), c0 = n * (colShape - 1);
    for (Eigen::Index c = 0; c < block.outerSize(); ++c)
      for (Eigen::SparseMatrix<double>::InnerIterator it(block, c); it; ++it) {
        const Eigen::Index row = r0 + (transpose ? it.col() : it.row()), col = c0 + (transpose ? it.row() : it.col());
        if (row >= col) triplets.emplace_back(int(row), int(col), it.value());
      }
  };
  for (size_t p = 0; p < all.size(); ++p) {
    const int r = all[p].reference, s = all[p].deformed;
    add(hr[p], r, r, false);
    add(hd[p], s, s, false);
    add(hm[p], r, s, false);  // rows reference, columns deformed
    add(hm[p], s, r, true);
  }
  Eigen::SparseMatrix<double> h(unknowns, unknowns);
  h.setFromTriplets(triplets.begin(), triplets.end());
  return h;
}

// The paper's stopping rule |g|^2 <= max(absoluteFactor * unknowns, relativeFactor * |g(start)|^2).
// Dense reduced problems update a BFGS model; the full one takes a Hessian per step.
numerics::NewtonOptions newtonOptions(const PathSolveOptions& options, Eigen::Index unknowns, const char* name, bool quasiNewton) {
  numerics::NewtonOptions newton;
  newton.name = name;
  newton.maxIterations = options.maxIterations;
  newton.gradientSquaredTolerance = options.absoluteFactor * double(unknowns);
  newton.relativeGradientSquaredTolerance = options.relativeFactor;
  newton.quasiNewton = quasiNewton;
  return newton;
}

PathSolveReport toPathReport(const numerics::NewtonReport& newton) {
  PathSolveReport report;
  report.iterations = newton.iterations;
  report.evaluations = newton.evaluations;
  report.gradientSquaredNorm = newton.gradientSquaredNorm;
  report.threshold = newton.gradientSquaredThreshold;
  report.status = newton.status;
  report.converged = newton.converged();
  return report;
}

}  // namespace

PathSolveReport minimisePathEnergyReduced(const EvaluationSpace& space, std::vector<Eigen::VectorXd>& shapes,
                                          const Eigen::MatrixXd& basis, const PathSolveOptions& options,
                                          const std::vector<Eigen::SparseMatrix<double>>* given) {
  checkPath(space.fineEnergy(), shapes, "reduced path energy");
  if (basis.cols() == 0 || basis.rows() != shapes.front().size())
    throw InvalidInputError("reduced path energy: basis is empty or has the wrong row count");
  if (!basis.allFinite()) throw InvalidInputError("reduced path energy: basis is not finite");
  const DeformationEnergy& evaluated = space.energy();
  const int count = int(shapes.size());
  if (given && int(given->size()) != count)
    throw InvalidInputError("reduced path energy: " + std::to_string(given->size()) + " rest Hessians for " +
                            std::to_string(count) + " shapes");
  const Eigen::Index d = basis.cols(), unknowns = d * (count - 2);
  // The evaluation space's rows of origins and basis (same reduced coordinates).
  std::vector<Eigen::VectorXd> origins(shapes.size());
  for (int k = 0; k < count; ++k) origins[size_t(k)] = space.restrict(shapes[size_t(k)]);
  const Eigen::MatrixXd evalBasis = space.restrictRows(basis);
  const auto evalShapes = [&](const Eigen::VectorXd& q) {
    std::vector<Eigen::VectorXd> x = origins;
    for (int k = 1; k + 1 < count; ++k) x[size_t(k)] += evalBasis * q.segment(d * (k - 1), d);
    return x;
  };
  // Quasi-Newton ([Brandt16 §6]: BFGS with a good initial Hessian): the Hessian model at the start, then
  // BFGS updates from gradients only (measured on the finger: L-BFGS with a rest-Hessian preconditioner
  // needed 200-400 evaluations, this 35).
  numerics::NewtonObjective<Eigen::MatrixXd> objective;
  objective.evaluate = [&](const Eigen::VectorXd& q, Eigen::VectorXd* gradient) {
    std::vector<Eigen::VectorXd> gradients;
    const double f = pathEnergyOrInfinity(evaluated, evalShapes(q), gradient ? &gradients : nullptr);
    if (gradient && std::isfinite(f)) {
      gradient->resize(unknowns);
      for (int k = 1; k + 1 < count; ++k) gradient->segment(d * (k - 1), d) = evalBasis.transpose() * gradients[size_t(k)];
    }
    return f;
  };
  std::vector<Eigen::SparseMatrix<double>> rest;  // kept: the model's Hessians reuse their storage
  objective.hessian = [&](const Eigen::VectorXd& q) {
    restHessians(evaluated, evalShapes(q), rest);
    return reducedHessianModel(rest, evalBasis, evaluated.numVertices());
  };
  Eigen::VectorXd q = Eigen::VectorXd::Zero(unknowns);
  const Eigen::MatrixXd start = given ? reducedHessianModel(*given, evalBasis, evaluated.numVertices()) : objective.hessian(q);
  PathSolveReport report = toPathReport(numerics::dampedNewton(objective, q, newtonOptions(options, unknowns, "reduced path energy", true), &start));
  for (int k = 1; k + 1 < count; ++k) shapes[size_t(k)] += basis * q.segment(d * (k - 1), d);
  return report;
}

PathSolveReport minimisePathEnergyFull(const DeformationEnergy& energy, std::vector<Eigen::VectorXd>& shapes,
                                       const PathSolveOptions& options) {
  checkPath(energy, shapes, "full path energy");
  const int count = int(shapes.size());
  const Eigen::Index n = shapes.front().size(), unknowns = n * (count - 2);
  const auto unpack = [&](const Eigen::VectorXd& x) {
    std::vector<Eigen::VectorXd> path = shapes;
    for (int k = 1; k + 1 < count; ++k) path[size_t(k)] = x.segment(n * (k - 1), n);
    return path;
  };
  numerics::NewtonObjective<Eigen::SparseMatrix<double>> objective;
  objective.evaluate = [&](const Eigen::VectorXd& x, Eigen::VectorXd* gradient) {
    std::vector<Eigen::VectorXd> gradients;
    const double f = pathEnergyOrInfinity(energy, unpack(x), gradient ? &gradients : nullptr);
    if (gradient && std::isfinite(f)) {
      gradient->resize(unknowns);
      for (int k = 1; k + 1 < count; ++k) gradient->segment(n * (k - 1), n) = gradients[size_t(k)];
    }
    return f;
  };
  objective.hessian = [&](const Eigen::VectorXd& x) { return pathHessian(energy, unpack(x)); };
  Eigen::VectorXd x(unknowns);
  for (int k = 1; k + 1 < count; ++k) x.segment(n * (k - 1), n) = shapes[size_t(k)];
  PathSolveReport report = toPathReport(numerics::dampedNewton(objective, x, newtonOptions(options, unknowns, "full path energy", false)));
  shapes = unpack(x);
  return report;
}

}  // namespace deformation_enrichment::shape_space
