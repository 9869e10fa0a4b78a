#include "deformation_enrichment/shape_space/geodesic_path.hpp"

#include <cmath>
#include <exception>
#include <limits>
#include <stdexcept>
#include <string>

#include <Eigen/Cholesky>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#ifdef DE_HAVE_CHOLMOD
#include <Eigen/CholmodSupport>
#endif

#include "deformation_enrichment/error.hpp"

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

// The 2 (K - 1) energy passes of eq. 4 (pair s, direction d: W(x_s, x_s+1) for d = 0, W(x_s+1, x_s) for d = 1).
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

// Runs body(p) for every pass, in parallel on meshes of >= 1000 vertices (pairs are independent; nested
// energy loops then run serially; on small meshes the OpenMP team's idle spinning costs more than the
// work on a loaded machine), and rethrows the first exception.
template <class Body>
void forEachPass(const std::vector<Pass>& all, Eigen::Index numVertices, const Body& body) {
  std::exception_ptr error;
#pragma omp parallel for schedule(dynamic) if (numVertices >= 1000)
  for (int p = 0; p < int(all.size()); ++p) {
    try {
      body(p);
    } catch (...) {
#pragma omp critical
      error = std::current_exception();
    }
  }
  if (error) std::rethrow_exception(error);
}

double gradientSquaredNorm(const std::vector<Eigen::VectorXd>& gradients) {
  double sum = 0.0;
  for (size_t k = 1; k + 1 < gradients.size(); ++k) sum += gradients[k].squaredNorm();
  return sum;
}

}  // namespace

double pathEnergy(const DeformationEnergy& energy, const std::vector<Eigen::VectorXd>& shapes,
                  std::vector<Eigen::VectorXd>* gradients) {
  const std::vector<Pass> all = passes(int(shapes.size()));
  std::vector<double> values(all.size(), 0.0);
  std::vector<Eigen::VectorXd> gradDeformed(gradients ? all.size() : 0), gradReference(gradients ? all.size() : 0);
  forEachPass(all, energy.numVertices(), [&](int p) {
    EnergyOutputs out;
    out.value = &values[size_t(p)];
    if (gradients) {
      out.gradientDeformed = &gradDeformed[size_t(p)];
      out.gradientReference = &gradReference[size_t(p)];
    }
    energy.evaluate(shapes[size_t(all[size_t(p)].reference)], shapes[size_t(all[size_t(p)].deformed)], out);
  });
  double sum = 0.0;
  for (double v : values) sum += v;  // eq. 4
  if (gradients) {
    gradients->assign(shapes.size(), Eigen::VectorXd::Zero(shapes.front().size()));
    for (size_t p = 0; p < all.size(); ++p) {
      (*gradients)[size_t(all[p].reference)] += gradReference[p];
      (*gradients)[size_t(all[p].deformed)] += gradDeformed[p];
    }
  }
  return sum;
}

PathSolveReport minimisePathEnergyReduced(const DeformationEnergy& energy, std::vector<Eigen::VectorXd>& shapes,
                                          const Eigen::MatrixXd& basis, const GhostMesh* ghost,
                                          const DeformationEnergy* ghostEnergy, const PathSolveOptions& options) {
  checkPath(energy, shapes, "reduced path energy");
  if (basis.cols() == 0 || basis.rows() != shapes.front().size())
    throw InvalidInputError("reduced path energy: basis is empty or has the wrong row count");
  if (!basis.allFinite()) throw InvalidInputError("reduced path energy: basis is not finite");
  if (ghost && !ghostEnergy) throw InvalidInputError("reduced path energy: a ghost mesh needs its energy");
  const DeformationEnergy& evaluated = ghost ? *ghostEnergy : energy;
  const int count = int(shapes.size());
  const Eigen::Index d = basis.cols(), unknowns = d * (count - 2);
  // Evaluation space: the ghost's rows of origins and basis (same reduced coordinates), or the fine ones.
  std::vector<Eigen::VectorXd> origins(shapes.size());
  for (int k = 0; k < count; ++k) origins[size_t(k)] = ghost ? ghost->restrict(shapes[size_t(k)]) : shapes[size_t(k)];
  const Eigen::MatrixXd evalBasis = ghost ? ghost->restrictRows(basis) : basis;
  if (evalBasis.rows() != 3 * evaluated.numVertices())
    throw InvalidInputError("reduced path energy: the ghost energy does not match the ghost mesh");
  const std::vector<Pass> all = passes(count);
  const auto evalShapes = [&](const Eigen::VectorXd& q) {
    std::vector<Eigen::VectorXd> x = origins;
    for (int k = 1; k + 1 < count; ++k) x[size_t(k)] += evalBasis * q.segment(d * (k - 1), d);
    return x;
  };

  PathSolveReport report;
  Eigen::VectorXd q = Eigen::VectorXd::Zero(unknowns), g(unknowns);
  Eigen::MatrixXd h(unknowns, unknowns);  // the exact reduced Hessian or its BFGS update
  // Value, reduced gradient B^T d(eq. 4)/dq and, if withHessian, a model of the reduced Hessian
  // B^T d2(eq. 4) B (dense: a few hundred unknowns), projected inside the parallel passes. The model takes
  // each term W(x_r, x_s) as its quadratic model 1/2 (x_s - x_r)^T H (x_s - x_r), H = d2d2 W (exact when
  // x_r = x_s: there d1d1 W = d2d2 W = -d1d2 W), so one d2d2 block per term gives all four blocks; the
  // reference derivatives (d1d1, d1d2) would cost 3.5 times as much (measured on the finger).
  const auto derivatives = [&](const Eigen::VectorXd& at, bool withHessian) {
    const std::vector<Eigen::VectorXd> x = evalShapes(at);
    std::vector<double> values(all.size(), 0.0);
    std::vector<Eigen::VectorXd> gr(all.size()), gd(all.size());
    std::vector<Eigen::MatrixXd> hd(all.size());
    forEachPass(all, evaluated.numVertices(), [&](int p) {
      Eigen::VectorXd gradReference, gradDeformed;
      Eigen::SparseMatrix<double> hessDeformed;
      EnergyOutputs out;
      out.value = &values[size_t(p)];
      out.gradientReference = &gradReference;
      out.gradientDeformed = &gradDeformed;
      if (withHessian) out.hessianDeformed = &hessDeformed;
      evaluated.evaluate(x[size_t(all[size_t(p)].reference)], x[size_t(all[size_t(p)].deformed)], out);
      gr[size_t(p)] = evalBasis.transpose() * gradReference;
      gd[size_t(p)] = evalBasis.transpose() * gradDeformed;
      if (withHessian) hd[size_t(p)] = evalBasis.transpose() * (hessDeformed * evalBasis);
    });
    ++report.evaluations;
    g.setZero();
    if (withHessian) h.setZero();
    double f = 0.0;
    const auto inner = [&](int k) { return k > 0 && k + 1 < count; };
    for (size_t p = 0; p < all.size(); ++p) {
      f += values[p];
      const int r = all[p].reference, s = all[p].deformed;
      if (inner(r)) g.segment(d * (r - 1), d) += gr[p];
      if (inner(s)) g.segment(d * (s - 1), d) += gd[p];
      if (!withHessian) continue;
      if (inner(r)) h.block(d * (r - 1), d * (r - 1), d, d) += hd[p];
      if (inner(s)) h.block(d * (s - 1), d * (s - 1), d, d) += hd[p];
      if (inner(r) && inner(s)) {
        h.block(d * (r - 1), d * (s - 1), d, d) -= hd[p];
        h.block(d * (s - 1), d * (r - 1), d, d) -= hd[p];
      }
    }
    return f;
  };
  double trialValue = 0.0;
  Eigen::VectorXd trialGradient;
  const auto trialWithGradient = [&](const Eigen::VectorXd& trial) {
    const Eigen::VectorXd kept = g;
    try {
      trialValue = derivatives(trial, false);
    } catch (const InvalidInputError&) {  // the step collapsed a triangle: too long
      trialValue = std::numeric_limits<double>::infinity();
    }
    trialGradient = g;
    g = kept;
    return std::isfinite(trialValue) ? trialValue : std::numeric_limits<double>::infinity();
  };
  const auto value = [&](const Eigen::VectorXd& trial) {
    ++report.evaluations;
    try {
      return pathEnergy(evaluated, evalShapes(trial));
    } catch (const InvalidInputError&) {  // the step collapsed a triangle: too long
      return std::numeric_limits<double>::infinity();
    }
  };

  // Quasi-Newton ([Brandt16 §6]: BFGS with a good initial Hessian): the Hessian model at the start, then
  // BFGS updates from gradients only. If no step descends, the model is recomputed once before giving up.
  double f = derivatives(q, true);
  if (!std::isfinite(f)) throw NumericalError("reduced path energy: eq. 4 is not finite at the start");
  const double f0 = f;
  report.threshold = std::max(options.absoluteFactor * double(unknowns), options.relativeFactor * g.squaredNorm());
  double damping = 1e-10;  // relative to the mean diagonal; at first only kills the rigid null space
  bool freshHessian = true;
  while (g.squaredNorm() > report.threshold && report.iterations < options.maxIterations) {
    ++report.iterations;
    const double diagScale = std::max(h.diagonal().cwiseAbs().mean(), 1e-300);
    bool accepted = false, roundOff = false;
    Eigen::VectorXd step;
    double alpha = 1.0;
    for (int attempt = 0; attempt < 40 && !accepted && !roundOff; ++attempt) {  // Levenberg-Marquardt
      Eigen::MatrixXd damped = h;
      damped.diagonal().array() += damping * diagScale;
      const Eigen::LLT<Eigen::MatrixXd> llt(damped);
      if (llt.info() != Eigen::Success) {
        damping *= 10.0;
        continue;
      }
      step = -llt.solve(g);
      const double decrement = -g.dot(step);
      if (!step.allFinite() || !(decrement > 0.0)) {
        damping *= 10.0;
        continue;
      }
      if (decrement <= 1e-14 * f0) {  // decrement at round-off: a minimiser to working precision
        roundOff = true;
        break;
      }
      alpha = 1.0;
      for (int ls = 0; ls < 30 && !accepted; ++ls, alpha *= 0.5) {  // Armijo backtracking
        // The full step is usually accepted: try it with the gradient (reused below), shorter ones by value.
        const double ft = ls == 0 ? trialWithGradient(q + step) : value(q + alpha * step);
        if (std::isfinite(ft) && ft <= f - 1e-4 * alpha * decrement) accepted = true;
        if (accepted) break;
      }
      damping = accepted ? std::max(damping * 0.1, 1e-10) : damping * 10.0;
    }
    if (roundOff) {
      report.converged = true;
      break;
    }
    if (!accepted) {
      if (freshHessian) break;  // no descent even with heavy damping: reported as unconverged below
      f = derivatives(q, true);
      freshHessian = true;
      damping = 1e-10;
      continue;
    }
    const Eigen::VectorXd s = alpha * step, gOld = g;
    q += s;
    if (alpha == 1.0) {
      f = trialValue;
      g = trialGradient;
    } else {
      f = derivatives(q, false);
    }
    freshHessian = false;
    const Eigen::VectorXd y = g - gOld;
    const Eigen::VectorXd hs = h * s;
    const double ys = y.dot(s), shs = s.dot(hs);
    if (ys > 1e-12 * std::sqrt(y.squaredNorm() * s.squaredNorm()) && shs > 0.0)  // keeps h positive definite
      h += (y * y.transpose()) / ys - (hs * hs.transpose()) / shs;  // BFGS update of the Hessian
  }
  report.gradientSquaredNorm = g.squaredNorm();
  report.converged = report.converged || report.gradientSquaredNorm <= report.threshold;
  for (int k = 1; k + 1 < count; ++k) shapes[size_t(k)] += basis * q.segment(d * (k - 1), d);
  return report;
}

PathSolveReport minimisePathEnergyFull(const DeformationEnergy& energy, std::vector<Eigen::VectorXd>& shapes,
                                       const PathSolveOptions& options) {
  checkPath(energy, shapes, "full path energy");
  const int count = int(shapes.size());
  const Eigen::Index n = shapes.front().size(), unknowns = n * (count - 2);
  const std::vector<Pass> all = passes(count);
  PathSolveReport report;
  std::vector<Eigen::VectorXd> gradients;
  double f = pathEnergy(energy, shapes, &gradients);
  ++report.evaluations;
  const double f0 = f;
  double squared = gradientSquaredNorm(gradients);
  report.threshold = std::max(options.absoluteFactor * double(unknowns), options.relativeFactor * squared);
#ifdef DE_HAVE_CHOLMOD
  Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Lower> solver;  // reports indefinite matrices
  solver.cholmod().print = 0;
#else
  Eigen::SimplicialLLT<Eigen::SparseMatrix<double>, Eigen::Lower> solver;
#endif
  bool analysed = false;
  double damping = 1e-10;  // relative to the mean diagonal; at first only kills the rigid null space
  while (squared > report.threshold && report.iterations < options.maxIterations) {
    ++report.iterations;
    // Hessian of eq. 4 (lower triangle) from the per-pass blocks; rows/columns of the fixed ends dropped.
    std::vector<Eigen::SparseMatrix<double>> hd(all.size()), hm(all.size()), hr(all.size());
    forEachPass(all, energy.numVertices(), [&](int p) {
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
      const int r = all[p].reference, dshape = all[p].deformed;
      add(hr[p], r, r, false);
      add(hd[p], dshape, dshape, false);
      add(hm[p], r, dshape, false);  // rows reference, columns deformed
      add(hm[p], dshape, r, true);
    }
    Eigen::SparseMatrix<double> h(unknowns, unknowns);
    h.setFromTriplets(triplets.begin(), triplets.end());
    Eigen::VectorXd g(unknowns);
    for (int k = 1; k + 1 < count; ++k) g.segment(n * (k - 1), n) = gradients[size_t(k)];
    const double diagScale = std::max(h.diagonal().cwiseAbs().mean(), 1e-300);
    if (!analysed) {
      solver.analyzePattern(h);
      analysed = true;
    }
    bool accepted = false;
    for (int attempt = 0; attempt < 40 && !accepted; ++attempt) {  // Levenberg-Marquardt
      Eigen::SparseMatrix<double> damped = h;
      for (Eigen::Index k = 0; k < damped.rows(); ++k) damped.coeffRef(k, k) += damping * diagScale;
      solver.factorize(damped);
      if (solver.info() != Eigen::Success) {
        damping *= 10.0;
        continue;
      }
      const Eigen::VectorXd step = -solver.solve(g);
      const double decrement = -g.dot(step);
      if (!step.allFinite() || !(decrement > 0.0)) {
        damping *= 10.0;
        continue;
      }
      if (decrement <= 1e-14 * f0) {  // Newton decrement at round-off: a minimiser to working precision
        report.gradientSquaredNorm = squared;
        report.converged = true;
        return report;
      }
      double alpha = 1.0;
      for (int ls = 0; ls < 30 && !accepted; ++ls, alpha *= 0.5) {  // Armijo backtracking
        std::vector<Eigen::VectorXd> trial = shapes;
        for (int k = 1; k + 1 < count; ++k) trial[size_t(k)] += alpha * step.segment(n * (k - 1), n);
        double ft = std::numeric_limits<double>::infinity();
        std::vector<Eigen::VectorXd> trialGradients;
        try {
          ft = pathEnergy(energy, trial, &trialGradients);
          ++report.evaluations;
        } catch (const InvalidInputError&) {  // the step collapsed a triangle: too long
        }
        if (std::isfinite(ft) && ft <= f - 1e-4 * alpha * decrement) {
          shapes = std::move(trial);
          gradients = std::move(trialGradients);
          f = ft;
          accepted = true;
        }
      }
      damping = accepted ? std::max(damping * 0.1, 1e-10) : damping * 10.0;
    }
    squared = gradientSquaredNorm(gradients);
    if (!accepted) break;  // no descent even with heavy damping: reported as unconverged below
  }
  report.gradientSquaredNorm = squared;
  report.converged = squared <= report.threshold;
  return report;
}

std::vector<Eigen::VectorXd> pathTangents(const DeformationEnergy& energy, const std::vector<Eigen::VectorXd>& shapes) {
  checkPath(energy, shapes, "path tangents");
  std::vector<Eigen::VectorXd> gradients;
  pathEnergy(energy, shapes, &gradients);
  std::vector<Eigen::VectorXd> tangents(shapes.size() - 2);
#ifdef DE_HAVE_CHOLMOD
  // One symbolic analysis (fill-reducing ordering, supernodes) for all shapes: their rest Hessians share
  // the mesh's sparsity pattern, so only the numeric factorisation is repeated (re-analysed should an
  // energy ever return a different pattern).
  Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Lower> llt;
  llt.cholmod().print = 0;
  Eigen::VectorXi analysedOuter, analysedInner;
#endif
  // Shape by shape: the supernodal factorisation runs a threaded BLAS, which oversubscribes the cores
  // inside an OpenMP loop over shapes (measured 2.4x slower on 2 cores).
  for (size_t k = 1; k + 1 < shapes.size(); ++k) {
    // eq. 9's metric d1d1 W(x, x) + d2d2 W(x, x) = 2 d2d2 W(x, x) (W(x, x) = 0 and its gradients vanish
    // there for every x, so d1d1 = -d1d2 = d2d2): one d2d2 pass. The ridge removes the rigid null space.
    Eigen::SparseMatrix<double> h = 2.0 * energy.hessianDeformed(shapes[k], shapes[k]);
    const double ridge = 1e-8 * std::max(h.diagonal().cwiseAbs().mean(), 1e-300);
    for (Eigen::Index i = 0; i < h.rows(); ++i) h.coeffRef(i, i) += ridge;
#ifdef DE_HAVE_CHOLMOD
    h.makeCompressed();
    const Eigen::Map<const Eigen::VectorXi> outer(h.outerIndexPtr(), h.outerSize() + 1), inner(h.innerIndexPtr(), h.nonZeros());
    if (analysedOuter.size() != outer.size() || analysedInner.size() != inner.size() || analysedOuter != outer ||
        analysedInner != inner) {
      llt.analyzePattern(h);
      analysedOuter = outer;
      analysedInner = inner;
    }
    llt.factorize(h);
    if (llt.info() == Eigen::Success) {
      tangents[k - 1] = -llt.solve(gradients[k]);
      continue;
    }
#endif
    const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(h);  // semi-definite up to round-off
    if (ldlt.info() != Eigen::Success) throw NumericalError("path tangents: rest Hessian factorisation failed");
    tangents[k - 1] = -ldlt.solve(gradients[k]);
  }
  return tangents;
}

}  // namespace deformation_enrichment::shape_space
