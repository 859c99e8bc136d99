// The dot product of the H-matrix's ACA and products.
#pragma once

#include <cstdint>

namespace bemcontact {

// (reassociated into SIMD lanes: the ACA's norm updates spend most of their
// time here; the order is fixed by n, so results do not depend on threads)
inline double dot(const double* a, const double* b, int64_t n) {
  double s = 0.0;
#pragma omp simd reduction(+ : s)
  for (int64_t i = 0; i < n; ++i) s += a[i] * b[i];
  return s;
}

}  // namespace bemcontact
