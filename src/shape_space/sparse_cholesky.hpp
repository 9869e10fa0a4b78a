#pragma once
// Sparse Cholesky factorisation of H + shift I for the shape-space solvers (private to the module): CHOLMOD's
// LLT when available (it reports indefinite matrices), else Eigen's SimplicialLLT. CHOLMOD chooses between
// its simplicial and supernodal factorisations by the flop count (CHOLMOD_AUTO): supernodal everywhere
// spent 75 % of a flow step on a 342-vertex mesh in OpenMP spin-waits inside cholmod_super_numeric, and
// simplicial everywhere made the 37k-unknown finger path 5x slower. The symbolic analysis (fill-reducing
// ordering) runs once while the sparsity pattern stays: every Hessian of one mesh shares the energy's
// pattern, so only the numeric factorisation is repeated.
#include <Eigen/SparseCore>
#ifdef _OPENMP
#include <omp.h>
#endif
#ifdef DE_HAVE_CHOLMOD
#include <Eigen/CholmodSupport>
#else
#include <Eigen/SparseCholesky>
#endif

namespace deformation_enrichment::shape_space::detail {

class SparseCholesky {
public:
#ifdef DE_HAVE_CHOLMOD
  SparseCholesky() {
    solver_.cholmod().print = 0;  // indefinite trials are expected: no warnings
    solver_.cholmod().supernodal = CHOLMOD_AUTO;
    solver_.cholmod().final_asis = 0;  // LL' (which fails for indefinite matrices), not LDL'
    solver_.cholmod().final_ll = 1;
  }
#endif

  /// Factorises h + shift I (the lower triangle of h is read; the shift goes to the factorisation, so h is not
  /// copied: measured, the copies' page faults were 7 % of a finger geodesic); false if that is not positive
  /// definite.
  bool factorize(const Eigen::SparseMatrix<double>& h, double shift) {
    if (!h.isCompressed()) {  // the factorisations read compressed storage
      Eigen::SparseMatrix<double> compressed = h;
      compressed.makeCompressed();
      return factorize(compressed, shift);
    }
    const Eigen::Map<const Eigen::VectorXi> outer(h.outerIndexPtr(), h.outerSize() + 1);
    const Eigen::Map<const Eigen::VectorXi> inner(h.innerIndexPtr(), h.nonZeros());
    if (outer.size() != outer_.size() || inner.size() != inner_.size() || outer != outer_ || inner != inner_) {
      solver_.analyzePattern(h);
      outer_ = outer;
      inner_ = inner;
    }
    solver_.setShift(shift);
#ifdef _OPENMP
    // CHOLMOD 3's supernodal factorisation asks OpenMP for a fixed 4 threads (CHOLMOD_OMP_NUM_THREADS) in its
    // zeroing and assembly loops; on 2 shared cores their spin-waits cost more than the loops (measured: 14 %
    // of a finger geodesic with OMP_NUM_THREADS=1). With dynamic adjustment (a per-thread setting) OpenMP
    // bounds such teams by this thread's team size and the load.
    const int dynamic = omp_get_dynamic();
    omp_set_dynamic(1);
    solver_.factorize(h);
    omp_set_dynamic(dynamic);
#else
    solver_.factorize(h);
#endif
    return solver_.info() == Eigen::Success;
  }

  Eigen::VectorXd solve(const Eigen::VectorXd& b) const { return solver_.solve(b); }

private:
#ifdef DE_HAVE_CHOLMOD
  Eigen::CholmodDecomposition<Eigen::SparseMatrix<double>, Eigen::Lower> solver_;
#else
  Eigen::SimplicialLLT<Eigen::SparseMatrix<double>, Eigen::Lower> solver_;
#endif
  Eigen::VectorXi outer_, inner_;  // the analysed pattern
};

}  // namespace deformation_enrichment::shape_space::detail
