#include "deformation_enrichment/shape_space/blas_threads.hpp"

#include <cstdlib>

#include <dlfcn.h>

namespace deformation_enrichment::shape_space {
namespace {

// OpenBLAS's own entry points, looked up at run time: the BLAS is chosen by Debian's alternatives
// (libblas.so.3), so it may be the reference BLAS, which has none.
template <class Function>
Function openBlasFunction(const char* name) {
  return reinterpret_cast<Function>(dlsym(RTLD_DEFAULT, name));
}

}  // namespace

bool preferSingleThreadedBlas() {
  if (std::getenv("OPENBLAS_NUM_THREADS") || std::getenv("GOTO_NUM_THREADS")) return false;
  const int threads = openBlasThreads();
  return threads > 1 && setOpenBlasThreads(1);
}

int openBlasThreads() {
  const auto getThreads = openBlasFunction<int (*)()>("openblas_get_num_threads");
  return getThreads ? getThreads() : 0;
}

bool setOpenBlasThreads(int n) {
  const auto setThreads = openBlasFunction<void (*)(int)>("openblas_set_num_threads");
  if (!setThreads || n < 1) return false;
  setThreads(n);
  return true;
}

}  // namespace deformation_enrichment::shape_space
