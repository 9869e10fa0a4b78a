#pragma once
// Sparse Cholesky factorisation of H + shift I, the one used by every Newton solve of the package (the tet
// simulator's and the shape space's). CHOLMOD's LL' when the package is built with it (it reports matrices
// that are not positive definite), choosing its simplicial or supernodal factorisation by the flop count;
// else, or when asked, Eigen's SimplicialLDLT with a positive pivot test. The symbolic analysis (the
// fill-reducing ordering) runs once while the sparsity pattern stays, so a sequence of Hessians of one mesh
// repeats only the numeric factorisation.
#include <Eigen/SparseCore>

#include <memory>

namespace deformation_enrichment::numerics {

enum class SparseCholeskyBackend {
  Default,          ///< CHOLMOD when built with it, else EigenSimplicial
  Cholmod,          ///< throws InvalidInputError when built without CHOLMOD
  EigenSimplicial,  ///< Eigen's SimplicialLDLT (a baseline, and the fallback)
};

/// Whether the package was built with CHOLMOD.
bool cholmodAvailable();

class SparseCholesky {
public:
  explicit SparseCholesky(SparseCholeskyBackend backend = SparseCholeskyBackend::Default);
  ~SparseCholesky();
  SparseCholesky(SparseCholesky&&) noexcept;
  SparseCholesky& operator=(SparseCholesky&&) noexcept;

  /// The backend in use (Default resolved).
  SparseCholeskyBackend backend() const;
  /// Factorises h + shift I, reading the lower triangle of h (not copied when compressed); false if that is
  /// not positive definite.
  bool factorize(const Eigen::SparseMatrix<double>& h, double shift = 0.0);
  /// Solves with the last successful factorisation.
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace deformation_enrichment::numerics
