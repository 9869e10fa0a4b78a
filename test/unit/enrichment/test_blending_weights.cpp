#include <gtest/gtest.h>

#include <cmath>
#include <random>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "deformation_enrichment/descriptors/descriptor_distance.hpp"
#include "deformation_enrichment/enrichment/blending_weights.hpp"
#include "deformation_enrichment/error.hpp"

using namespace deformation_enrichment;
using namespace deformation_enrichment::enrichment;

namespace {
hermite::MomentList randomList(std::mt19937& rng, int first, int last, int channels) {
  std::normal_distribution<double> normal;
  hermite::MomentList list(first, last, channels);
  for (Eigen::Index k = 0; k < list.values().size(); ++k) list.values()[k] = normal(rng);
  return list;
}
}  // namespace

TEST(BlendingWeights, VectorisedCorrelationMatchesPerExampleDistancesAndEq15) {
  std::mt19937 rng(41);
  std::vector<hermite::MomentList> rho, mu;
  for (int i = 0; i < 37; ++i) {
    rho.push_back(randomList(rng, 0, 3, 1));
    mu.push_back(randomList(rng, 1, 2, 3));
  }
  mu[4].values().setZero();  // a zero example descriptor: d_u = 1 against a non-zero query
  const ExampleDescriptorTable table(rho, mu);
  const hermite::MomentList queryRho = randomList(rng, 0, 3, 1), queryMu = randomList(rng, 1, 2, 3);
  const KernelWidths widths{0.7, 0.8};
  Correlation out;
  correlate(table, queryRho, queryMu, widths, out);
  for (int i = 0; i < 37; ++i) {
    const double dRho = descriptors::siteDistance(queryRho, rho[i]);
    const double dU = descriptors::deformationDistance(queryMu, mu[i]);
    EXPECT_NEAR(out.dRho[i], dRho, 1e-12);
    EXPECT_NEAR(out.dU[i], dU, 1e-12);
    // eq. (15) written out.
    EXPECT_NEAR(out.weights[i], std::exp(-dRho * dRho / (2 * 0.49) - dU * dU / (2 * 0.64)), 1e-14);
  }
  EXPECT_EQ(out.dU[4], 1.0);
  EXPECT_TRUE(out.weights.isApprox(blendingWeights(out.dRho, out.dU, widths)));
  // The query itself among the examples gets weight 1.
  rho.push_back(queryRho);
  mu.push_back(queryMu);
  correlate(ExampleDescriptorTable(rho, mu), queryRho, queryMu, widths, out);
  EXPECT_NEAR(out.weights[37], 1.0, 1e-12);
  // A zero query against zero / non-zero examples: d_u 0 / 1.
  hermite::MomentList zero(1, 2, 3);
  correlate(table, queryRho, zero, widths, out);
  EXPECT_EQ(out.dU[4], 0.0);
  EXPECT_EQ(out.dU[0], 1.0);
  EXPECT_TRUE(out.weights.allFinite());
}

// A table past the threshold is correlated in blocks shared among threads: the numbers of every example,
// those next to block boundaries and the lone last one included, match the per-example distances and do not
// depend on the thread count.
TEST(BlendingWeights, LargeTablesGiveEveryExampleTheSameNumbersOnAnyThreadCount) {
  std::mt19937 rng(47);
  std::vector<hermite::MomentList> rho, mu;
  const int count = 3 * 4096 * 3 + 1;  // past the parallel threshold, with one example after the last full block
  for (int i = 0; i < count; ++i) {
    rho.push_back(randomList(rng, 0, 3, 1));
    mu.push_back(randomList(rng, 1, 2, 3));
  }
  const ExampleDescriptorTable table(rho, mu);
  const hermite::MomentList queryRho = randomList(rng, 0, 3, 1), queryMu = randomList(rng, 1, 2, 3);
  const KernelWidths widths{2.0, 0.8};
  const auto correlateOn = [&](int threads) {
#ifdef _OPENMP
    omp_set_num_threads(threads);
#else
    (void)threads;
#endif
    Correlation out;
    correlate(table, queryRho, queryMu, widths, out);
    return out;
  };
  const Correlation one = correlateOn(1), two = correlateOn(2);
#ifdef _OPENMP
  omp_set_num_threads(omp_get_num_procs());
#endif
  EXPECT_TRUE(one.dRho == two.dRho);
  EXPECT_TRUE(one.dU == two.dU);
  EXPECT_TRUE(one.weights == two.weights);
  for (const int i : {0, 4095, 4096, 4097, count / 2, count - 2, count - 1}) {
    EXPECT_NEAR(two.dRho[i], descriptors::siteDistance(queryRho, rho[i]), 1e-12) << i;
    EXPECT_NEAR(two.dU[i], descriptors::deformationDistance(queryMu, mu[i]), 1e-12) << i;
  }
}

TEST(BlendingWeights, BadInput) {
  std::mt19937 rng(43);
  std::vector<hermite::MomentList> rho{randomList(rng, 0, 3, 1)}, mu{randomList(rng, 1, 2, 3)};
  EXPECT_THROW(ExampleDescriptorTable({}, {}), InvalidInputError);
  EXPECT_THROW(ExampleDescriptorTable(rho, {}), InvalidInputError);
  std::vector<hermite::MomentList> mixed{rho[0], randomList(rng, 0, 2, 1)};
  EXPECT_THROW(ExampleDescriptorTable(mixed, {mu[0], mu[0]}), InvalidInputError);
  const ExampleDescriptorTable table(rho, mu);
  Correlation out;
  EXPECT_THROW(correlate(table, rho[0], mu[0], KernelWidths{0.0, 1.0}, out), InvalidInputError);
  EXPECT_THROW(correlate(table, randomList(rng, 0, 2, 1), mu[0], KernelWidths{}, out), InvalidInputError);
  hermite::MomentList bad = mu[0];
  bad.values()[2] = NAN;
  EXPECT_THROW(correlate(table, rho[0], bad, KernelWidths{}, out), InvalidInputError);
  EXPECT_THROW(ExampleDescriptorTable(rho, {bad}), InvalidInputError);
  EXPECT_THROW(blendingWeights(Eigen::VectorXd::Ones(2), Eigen::VectorXd::Ones(3), KernelWidths{}), InvalidInputError);
}
