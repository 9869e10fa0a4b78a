#pragma once
// The shape-space loops over shapes (private to the module): body(i) for i = 0 .. count - 1, over the OpenMP
// team when `parallel` (dynamic schedule: the shapes' solves differ in length), and the first exception a
// body threw rethrown after the loop (an exception must not leave an OpenMP region).
#include <exception>

#include <Eigen/Core>
#ifdef _OPENMP
#include <omp.h>
#endif

namespace deformation_enrichment::shape_space::detail {

/// Below this many vertices a pass runs serially: the OpenMP team's idle spinning costs more than the work
/// (measured: a 3-step smoothing of a 366-vertex MD2 clip took 4.7 s with 2 threads, 0.6 s serially, on a
/// loaded 2-core machine).
constexpr Eigen::Index kParallelVertices = 1000;

/// The team size a parallelFor may use, and the calling thread's index in it (per-thread scratch).
inline int maxThreads() {
#ifdef _OPENMP
  return omp_get_max_threads();
#else
  return 1;
#endif
}
inline int threadIndex() {
#ifdef _OPENMP
  return omp_get_thread_num();
#else
  return 0;
#endif
}

template <class Body>
void parallelFor(int count, bool parallel, const Body& body) {
  if (!parallel) {  // no OpenMP region at all: inside even an inactive one, a body's own parallel regions
    for (int i = 0; i < count; ++i) body(i);  // (CHOLMOD's) would get a nested team of fresh threads
    return;
  }
  std::exception_ptr error;
#pragma omp parallel for schedule(dynamic)
  for (int i = 0; i < count; ++i) {
    try {
      body(i);
    } catch (...) {
#pragma omp critical(de_parallel_for_error)
      if (!error) error = std::current_exception();
    }
  }
  if (error) std::rethrow_exception(error);
}

}  // namespace deformation_enrichment::shape_space::detail
