// LAPACK and BLAS routines (Fortran calling convention, 32-bit integers) as
// function-pointer tables, filled at run time from the capsules of
// scipy.linalg.cython_lapack and scipy.linalg.cython_blas (python/
// hmatrix_bindings.cpp), so that the build needs no LAPACK or BLAS.
#pragma once

namespace bemcontact {

// LAPACK routines of the low-rank truncation (la/lowrank.cpp).
struct Lapack {
  void (*dgeqrf)(int*, int*, double*, int*, double*, double*, int*, int*) = nullptr;
  void (*dormqr)(char*, char*, int*, int*, int*, double*, int*, double*, double*, int*,
                 double*, int*, int*) = nullptr;
  void (*dgesvd)(char*, char*, int*, int*, double*, int*, double*, double*, int*, double*,
                 int*, double*, int*, int*) = nullptr;
  // optional (divide and conquer, faster than dgesvd for the small cores)
  void (*dgesdd)(char*, int*, int*, double*, int*, double*, double*, int*, double*, int*,
                 double*, int*, int*, int*) = nullptr;
  bool ok() const { return dgeqrf && dormqr && dgesvd; }
};

// BLAS and LAPACK routines of the H-LU's dense kernels (hmat/hlu.cpp).
struct Blas {
  void (*dgemm)(char*, char*, int*, int*, int*, double*, double*, int*, double*, int*, double*,
                double*, int*) = nullptr;
  void (*dtrsm)(char*, char*, char*, char*, int*, int*, double*, double*, int*, double*,
                int*) = nullptr;
  void (*dgetrf)(int*, int*, double*, int*, int*, int*) = nullptr;
  void (*dlaswp)(int*, double*, int*, int*, int*, int*, int*) = nullptr;
  bool ok() const { return dgemm && dtrsm && dgetrf && dlaswp; }
};

}  // namespace bemcontact
