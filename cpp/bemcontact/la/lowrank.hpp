// Low-rank truncation (QR of both factors + SVD of the small core, LAPACK
// from SciPy): the recompression of the H-matrix's ACA blocks and every
// low-rank sum of the H-LU.
#pragma once

#include <cstdint>
#include <vector>

#include "la/lapack.hpp"

namespace bemcontact {

// Truncate the low-rank product U V^T (U: m x k, V: n x k, column-major) to
// the smallest rank whose discarded singular values have a 2-norm <= eps
// times the product's Frobenius norm, or <= abs_tol when that is larger (QR
// of both factors, SVD of the k x k core).  k is updated; rank 0 products
// are left alone.
void truncate_lowrank(std::vector<double>& U, std::vector<double>& V, int64_t m, int64_t n,
                      int& k, double eps, const Lapack& lapack, double abs_tol = 0.0);

}  // namespace bemcontact
