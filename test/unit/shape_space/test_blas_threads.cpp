// The shape-space tools' BLAS choice (blas_threads.hpp) and what depends on it: flowTangents solves shapes
// in parallel only with a single-threaded BLAS, and both ways give the same tangents (up to the BLAS's
// round-off: a threaded BLAS may sum in another order).
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>
#include <vector>

#include "deformation_enrichment/shape_space/blas_threads.hpp"
#include "deformation_enrichment/shape_space/discrete_shells.hpp"
#include "deformation_enrichment/shape_space/path_energy.hpp"
#include "flow_test_sequences.hpp"

namespace ss = deformation_enrichment::shape_space;
using namespace ss::test;

namespace {

// Restores OpenBLAS's thread count and OPENBLAS_NUM_THREADS when a test ends.
class BlasThreads : public ::testing::Test {
protected:
  void SetUp() override {
    threads_ = ss::openBlasThreads();
    const char* variable = std::getenv("OPENBLAS_NUM_THREADS");
    hadVariable_ = variable != nullptr;
    if (hadVariable_) variable_ = variable;
    unsetenv("OPENBLAS_NUM_THREADS");
  }
  void TearDown() override {
    if (threads_ > 0) ss::setOpenBlasThreads(threads_);
    if (hadVariable_) setenv("OPENBLAS_NUM_THREADS", variable_.c_str(), 1);
  }
  int threads_ = 0;
  bool hadVariable_ = false;
  std::string variable_;
};

}  // namespace

TEST_F(BlasThreads, OpenBlasIsMadeSingleThreadedUnlessTheUserChose) {
  if (threads_ == 0) {  // Debian's reference BLAS (docs/testing.md: the tests also run with it): nothing to set
    EXPECT_FALSE(ss::preferSingleThreadedBlas());
    EXPECT_FALSE(ss::setOpenBlasThreads(2));
    return;
  }
  ASSERT_TRUE(ss::setOpenBlasThreads(2));
  ASSERT_EQ(ss::openBlasThreads(), 2);
  setenv("OPENBLAS_NUM_THREADS", "2", 1);  // the user's choice stands
  EXPECT_FALSE(ss::preferSingleThreadedBlas());
  EXPECT_EQ(ss::openBlasThreads(), 2);
  unsetenv("OPENBLAS_NUM_THREADS");
  EXPECT_TRUE(ss::preferSingleThreadedBlas());
  EXPECT_EQ(ss::openBlasThreads(), 1);
  EXPECT_FALSE(ss::preferSingleThreadedBlas());  // already single-threaded: nothing changed
  EXPECT_FALSE(ss::setOpenBlasThreads(0));
}

TEST_F(BlasThreads, FlowTangentsAreTheSameInParallelAndShapeByShape) {
  if (threads_ == 0) GTEST_SKIP() << "the BLAS is not OpenBLAS: flowTangents always runs in parallel";
  const FlatMesh base = bumpyGrid(33, 5);  // 1089 vertices: above the parallel threshold
  const ss::DiscreteShells energy(base.triangles, base.vertices.size() / 3, ss::DiscreteShellsOptions::hyperelastic());
  std::vector<Eigen::VectorXd> shapes;
  for (int k = 0; k < 5; ++k) shapes.push_back(bent(base.vertices, 0.3 + 0.4 * k, 0.02 * k));
  ss::setOpenBlasThreads(1);  // parallel over shapes
  const std::vector<Eigen::VectorXd> parallel = ss::flowTangents(energy, shapes, false);
  ss::setOpenBlasThreads(2);  // shape by shape
  const std::vector<Eigen::VectorXd> serial = ss::flowTangents(energy, shapes, false);
  ASSERT_EQ(parallel.size(), serial.size());
  for (size_t k = 0; k < serial.size(); ++k) {
    // The ridge of 1e-8 (path_energy.cpp) makes the systems' condition ~1e8: round-off of 1e-16 may grow to
    // ~1e-8 relative (measured 3e-10 to 8e-10 here); a mixed-up shape or factor would differ by O(1).
    EXPECT_LE((parallel[k] - serial[k]).norm(), 1e-6 * serial[k].norm()) << "shape " << k;
    if (k > 0 && k + 1 < serial.size()) {
      EXPECT_GT(serial[k].norm(), 0.0) << "shape " << k;  // not trivially equal
    }
  }
}
