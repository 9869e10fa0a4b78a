#include "deformation_enrichment/numerics/sparse_cholesky.hpp"

#include <Eigen/SparseCholesky>
#ifdef DE_HAVE_CHOLMOD
#include <Eigen/CholmodSupport>
#endif
#ifdef _OPENMP
#include <omp.h>
#endif

#include "deformation_enrichment/error.hpp"

namespace deformation_enrichment::numerics {

bool cholmodAvailable() {
#ifdef DE_HAVE_CHOLMOD
  return true;
#else
  return false;
#endif
}

struct SparseCholesky::Impl {
  SparseCholeskyBackend backend = SparseCholeskyBackend::EigenSimplicial;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower> ldlt;
#ifdef DE_HAVE_CHOLMOD
  Eigen::CholmodDecomposition<Eigen::SparseMatrix<double>, Eigen::Lower> cholmod;
#endif
  Eigen::VectorXi outer, inner;  // the analysed pattern

  void analyseIfNew(const Eigen::SparseMatrix<double>& h) {
    const Eigen::Map<const Eigen::VectorXi> o(h.outerIndexPtr(), h.outerSize() + 1);
    const Eigen::Map<const Eigen::VectorXi> i(h.innerIndexPtr(), h.nonZeros());
    if (o.size() == outer.size() && i.size() == inner.size() && o == outer && i == inner) return;
#ifdef DE_HAVE_CHOLMOD
    if (backend == SparseCholeskyBackend::Cholmod) cholmod.analyzePattern(h);
#endif
    if (backend == SparseCholeskyBackend::EigenSimplicial) ldlt.analyzePattern(h);
    outer = o;
    inner = i;
  }

  bool factorizeCholmod([[maybe_unused]] const Eigen::SparseMatrix<double>& h, [[maybe_unused]] double shift) {
#ifdef DE_HAVE_CHOLMOD
    cholmod.setShift(shift);
#ifdef _OPENMP
    // CHOLMOD 3's supernodal factorisation asks OpenMP for a fixed 4 threads (CHOLMOD_OMP_NUM_THREADS) in its
    // zeroing and assembly loops; on 2 shared cores their spin-waits cost more than the loops (measured: 14 %
    // of a finger geodesic, 40 % of the factorisation time of a 49k-tet Newton solve). With dynamic
    // adjustment (a per-thread setting) OpenMP bounds such teams by this thread's team size and the load.
    const int dynamic = omp_get_dynamic();
    omp_set_dynamic(1);
    cholmod.factorize(h);
    omp_set_dynamic(dynamic);
#else
    cholmod.factorize(h);
#endif
    return cholmod.info() == Eigen::Success;
#else
    return false;
#endif
  }
};

SparseCholesky::SparseCholesky(SparseCholeskyBackend backend) : impl_(std::make_unique<Impl>()) {
  if (backend == SparseCholeskyBackend::Cholmod && !cholmodAvailable())
    throw InvalidInputError("SparseCholesky: CHOLMOD requested but the package was built without it");
  if (backend == SparseCholeskyBackend::Default)
    backend = cholmodAvailable() ? SparseCholeskyBackend::Cholmod : SparseCholeskyBackend::EigenSimplicial;
  impl_->backend = backend;
#ifdef DE_HAVE_CHOLMOD
  impl_->cholmod.cholmod().print = 0;  // indefinite trials are expected: no warnings
  impl_->cholmod.cholmod().supernodal = CHOLMOD_AUTO;
  impl_->cholmod.cholmod().final_asis = 0;  // LL' (which fails for indefinite matrices), not LDL'
  impl_->cholmod.cholmod().final_ll = 1;
#endif
}

SparseCholesky::~SparseCholesky() = default;
SparseCholesky::SparseCholesky(SparseCholesky&&) noexcept = default;
SparseCholesky& SparseCholesky::operator=(SparseCholesky&&) noexcept = default;

SparseCholeskyBackend SparseCholesky::backend() const { return impl_->backend; }

bool SparseCholesky::factorize(const Eigen::SparseMatrix<double>& h, double shift) {
  if (!h.isCompressed()) {  // the factorisations read compressed storage
    Eigen::SparseMatrix<double> compressed = h;
    compressed.makeCompressed();
    return factorize(compressed, shift);
  }
  impl_->analyseIfNew(h);
  if (impl_->backend == SparseCholeskyBackend::Cholmod) return impl_->factorizeCholmod(h, shift);
  impl_->ldlt.setShift(shift);
  impl_->ldlt.factorize(h);
  return impl_->ldlt.info() == Eigen::Success && impl_->ldlt.vectorD().minCoeff() > 0.0;
}

Eigen::VectorXd SparseCholesky::solve(const Eigen::VectorXd& b) const {
#ifdef DE_HAVE_CHOLMOD
  if (impl_->backend == SparseCholeskyBackend::Cholmod) return impl_->cholmod.solve(b);
#endif
  return impl_->ldlt.solve(b);
}

}  // namespace deformation_enrichment::numerics
