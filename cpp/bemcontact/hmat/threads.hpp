// The calling thread's number in its OpenMP team (0 without OpenMP): the
// index of its thread-private accumulators in the H-matrix build and products.
#pragma once

#ifdef _OPENMP
#include <omp.h>
#endif

namespace bemcontact {

inline int thread_num() {
#ifdef _OPENMP
  return omp_get_thread_num();
#else
  return 0;
#endif
}

}  // namespace bemcontact
