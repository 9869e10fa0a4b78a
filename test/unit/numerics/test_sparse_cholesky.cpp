// The one sparse Cholesky of the package, both backends, against Eigen's dense LLT: solves, the
// positive-definite test, the shift, and a new sparsity pattern after an old one.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/SparseCore>
#include <random>
#include <vector>

#include "deformation_enrichment/error.hpp"
#include "deformation_enrichment/numerics/sparse_cholesky.hpp"

using namespace deformation_enrichment;
using numerics::SparseCholesky;
using numerics::SparseCholeskyBackend;

namespace {

// A 1D Laplacian-like band matrix plus `diagonal` I, n x n: positive definite for diagonal > 0 (the band's
// eigenvalues lie in [0, 4]), indefinite for diagonal < 0; `reach` sets the bandwidth (the pattern).
Eigen::SparseMatrix<double> band(int n, double diagonal, int reach) {
  std::vector<Eigen::Triplet<double>> entries;
  for (int i = 0; i < n; ++i) {
    entries.emplace_back(i, i, 2.0 + diagonal + (reach > 1 ? 1.0 : 0.0));
    for (int k = 1; k <= reach && i + k < n; ++k) entries.emplace_back(i + k, i, k == 1 ? -1.0 : -0.5 / k);
  }
  Eigen::SparseMatrix<double> lower(n, n);
  lower.setFromTriplets(entries.begin(), entries.end());
  return lower;
}

std::vector<SparseCholeskyBackend> backends() {
  std::vector<SparseCholeskyBackend> out{SparseCholeskyBackend::EigenSimplicial};
  if (numerics::cholmodAvailable()) out.push_back(SparseCholeskyBackend::Cholmod);
  return out;
}

}  // namespace

TEST(SparseCholesky, SolvesLikeDenseCholeskyOnEveryBackend) {
  std::mt19937 rng(5);
  std::normal_distribution<double> normal;
  Eigen::VectorXd b(200);
  for (Eigen::Index i = 0; i < b.size(); ++i) b[i] = normal(rng);
  for (int reach : {1, 3}) {
    const Eigen::SparseMatrix<double> lower = band(200, 0.1, reach);
    const Eigen::MatrixXd full = Eigen::MatrixXd(lower).selfadjointView<Eigen::Lower>();
    const Eigen::VectorXd expected = full.llt().solve(b);
    for (SparseCholeskyBackend backend : backends()) {
      SparseCholesky cholesky(backend);
      ASSERT_TRUE(cholesky.factorize(lower));
      EXPECT_LT((cholesky.solve(b) - expected).norm(), 1e-12 * expected.norm()) << "reach " << reach;
    }
  }
}

TEST(SparseCholesky, RefusesIndefiniteMatricesAndTheShiftMakesThemDefinite) {
  const Eigen::SparseMatrix<double> indefinite = band(100, -1.0, 1);  // eigenvalues in [-1, 3]
  const Eigen::MatrixXd full = Eigen::MatrixXd(indefinite).selfadjointView<Eigen::Lower>();
  Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(100, -1.0, 1.0);
  for (SparseCholeskyBackend backend : backends()) {
    SparseCholesky cholesky(backend);
    EXPECT_FALSE(cholesky.factorize(indefinite));
    ASSERT_TRUE(cholesky.factorize(indefinite, 1.5));
    const Eigen::MatrixXd shifted = full + 1.5 * Eigen::MatrixXd::Identity(100, 100);
    EXPECT_LT((cholesky.solve(b) - shifted.llt().solve(b)).norm(), 1e-12 * b.norm());
  }
}

TEST(SparseCholesky, ANewPatternIsAnalysedAgain) {
  const Eigen::VectorXd b = Eigen::VectorXd::Ones(50);
  for (SparseCholeskyBackend backend : backends()) {
    SparseCholesky cholesky(backend);
    for (int reach : {1, 4, 1}) {
      const Eigen::SparseMatrix<double> lower = band(50, 0.2, reach);
      const Eigen::MatrixXd full = Eigen::MatrixXd(lower).selfadjointView<Eigen::Lower>();
      ASSERT_TRUE(cholesky.factorize(lower));
      EXPECT_LT((cholesky.solve(b) - full.llt().solve(b)).norm(), 1e-12 * b.norm()) << "reach " << reach;
    }
  }
}

TEST(SparseCholesky, DefaultIsCholmodWhenBuiltWithIt) {
  const SparseCholesky cholesky;
  EXPECT_EQ(cholesky.backend(), numerics::cholmodAvailable() ? SparseCholeskyBackend::Cholmod
                                                             : SparseCholeskyBackend::EigenSimplicial);
  if (!numerics::cholmodAvailable()) {
    EXPECT_THROW(SparseCholesky{SparseCholeskyBackend::Cholmod}, InvalidInputError);
  }
}
