// H-LU: an LU factorization of a body's compressed system matrix A (an
// HMatrix) in hierarchical-matrix arithmetic.  The flat block list of the
// HMatrix is rebuilt into its block tree (2 x 2 children per
// non-admissible block of two non-leaf clusters), then factored by the
// recursive block LU
//
//   A11 = L11 U11;  L11 U12 = A12;  L21 U11 = A21;
//   A22 - L21 U12 = L22 U22,
//
// with every low-rank sum truncated (QR + SVD) to the relative accuracy eps.
// Pivoting is partial within each dense diagonal leaf (the permutation is
// applied to the leaf's block row).  Dense kernels are BLAS/LAPACK routines
// taken at run time from SciPy (no link-time BLAS).  Used to solve A X = B for
// many right-hand sides (the contact condensation).
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "hmat/hmatrix.hpp"
#include "la/lapack.hpp"
#include "parallel.hpp"

namespace bemcontact {

struct HNode;

class HLU {
 public:
  // Factor A + U V^T (U, V: 3N x r, row-major, original dof order; r may be
  // 0): a low-rank update, e.g. to make a floating body's A nonsingular.
  // OpenMP tasks on `threads` threads (independent blocks of the recursion).
  HLU(const HMatrix& h, const Lapack& lapack, const Blas& blas, double eps,
      const double* U = nullptr, const double* V = nullptr, int64_t r = 0, int threads = 1);
  ~HLU();
  // Solve A X = B in place; b is 3N x k, row-major, original dof order.
  void solve(double* b, int64_t k) const;
  int64_t n_dofs() const { return 3 * n_; }
  int64_t stored_doubles() const;
  double factor_seconds() const { return factor_s_; }
  // largest rank of a low-rank block after the factorization
  int max_rank() const;

 private:
  std::unique_ptr<HNode> build(int tau, int sigma, const HMatrix& h,
                               const std::vector<int64_t>& index);
  void lu(HNode& a, ExceptionGuard& guard) const;

  int64_t n_ = 0;
  std::vector<int64_t> perm_;
  std::vector<HCluster> clusters_;
  Lapack lapack_;
  Blas blas_;
  double eps_ = 1e-6;
  std::unique_ptr<HNode> root_;
  std::vector<HNode*> leaves_;  // during the construction only
  double factor_s_ = 0.0;

  friend struct HArith;
};

}  // namespace bemcontact
