// Low-rank truncation (see lowrank.hpp).
#include "la/lowrank.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace bemcontact {

namespace {
// SVD of the k x k column-major matrix a (destroyed): a = W diag(s) Zt.
void core_svd(double* a, int k, double* s, double* W, double* Zt, const Lapack& lapack) {
  int info = 0, lw = -1;
  double wq = 0.0;
  if (lapack.dgesdd) {
    char jobz = 'A';
    std::vector<int> iwork(8 * static_cast<size_t>(k));
    lapack.dgesdd(&jobz, &k, &k, a, &k, s, W, &k, Zt, &k, &wq, &lw, iwork.data(), &info);
    lw = std::max(static_cast<int>(wq), 1);
    std::vector<double> work(lw);
    lapack.dgesdd(&jobz, &k, &k, a, &k, s, W, &k, Zt, &k, work.data(), &lw, iwork.data(), &info);
    if (info == 0) return;
    // dgesdd did not converge (rare): fall through to dgesvd on a fresh copy is not
    // possible (a destroyed), so report it
    throw std::runtime_error("H-LU: dgesdd failed");
  }
  char jobu = 'A', jobvt = 'A';
  lapack.dgesvd(&jobu, &jobvt, &k, &k, a, &k, s, W, &k, Zt, &k, &wq, &lw, &info);
  lw = std::max(static_cast<int>(wq), 1);
  std::vector<double> work(lw);
  lapack.dgesvd(&jobu, &jobvt, &k, &k, a, &k, s, W, &k, Zt, &k, work.data(), &lw, &info);
  if (info) throw std::runtime_error("H-LU: dgesvd failed");
}

// Smallest rank whose discarded singular values (sv, descending, r of them)
// have a 2-norm <= max(eps |sv|_2, abs_tol).
int64_t truncation_rank(const double* sv, int64_t r, double eps, double abs_tol) {
  double total = 0.0;
  for (int64_t i = 0; i < r; ++i) total += sv[i] * sv[i];
  const double tol = std::max(eps * std::sqrt(total), abs_tol);
  int64_t keep = r;
  double tail = 0.0;
  while (keep > 0 && std::sqrt(tail + sv[keep - 1] * sv[keep - 1]) <= tol) {
    tail += sv[keep - 1] * sv[keep - 1];
    --keep;
  }
  return keep;
}

// Truncated SVD of the dense column-major m x n matrix P (destroyed): U V^T
// of the rank truncation_rank gives.
void dense_lowrank(std::vector<double>& P, int64_t m, int64_t n, double eps, double abs_tol,
                   const Lapack& lapack, std::vector<double>& U, std::vector<double>& V, int& k) {
  const int64_t r = std::min(m, n);
  int im = static_cast<int>(m), in = static_cast<int>(n), ir = static_cast<int>(r), info = 0;
  std::vector<double> sv(r), Um(m * r), Vt(r * n);
  int lw = -1;
  double wq = 0.0;
  if (lapack.dgesdd) {  // divide and conquer: several times faster than dgesvd here
    char job = 'S';
    std::vector<int> iwork(8 * static_cast<size_t>(r));
    lapack.dgesdd(&job, &im, &in, P.data(), &im, sv.data(), Um.data(), &im, Vt.data(), &ir, &wq,
                  &lw, iwork.data(), &info);
    lw = std::max(static_cast<int>(wq), 1);
    std::vector<double> work(lw);
    lapack.dgesdd(&job, &im, &in, P.data(), &im, sv.data(), Um.data(), &im, Vt.data(), &ir,
                  work.data(), &lw, iwork.data(), &info);
    if (info) throw std::runtime_error("H-LU: dgesdd failed");
  } else {
    char job = 'S';
    lapack.dgesvd(&job, &job, &im, &in, P.data(), &im, sv.data(), Um.data(), &im, Vt.data(), &ir,
                  &wq, &lw, &info);
    lw = std::max(static_cast<int>(wq), 1);
    std::vector<double> work(lw);
    lapack.dgesvd(&job, &job, &im, &in, P.data(), &im, sv.data(), Um.data(), &im, Vt.data(), &ir,
                  work.data(), &lw, &info);
    if (info) throw std::runtime_error("H-LU: dgesvd failed");
  }
  const int64_t keep = truncation_rank(sv.data(), r, eps, abs_tol);
  std::vector<double> nu(m * keep), nv(n * keep);
  for (int64_t l = 0; l < keep; ++l) {
    for (int64_t i = 0; i < m; ++i) nu[l * m + i] = Um[l * m + i] * sv[l];
    for (int64_t j = 0; j < n; ++j) nv[l * n + j] = Vt[j * r + l];
  }
  U.swap(nu);
  V.swap(nv);
  k = static_cast<int>(keep);
}
}  // namespace

void truncate_lowrank(std::vector<double>& U, std::vector<double>& V, int64_t m, int64_t n,
                      int& k, double eps, const Lapack& lapack, double abs_tol) {
  if (!lapack.ok() || k == 0) return;
  if (k > m || k > n) {
    // more terms than rows or columns: QR would not reduce; truncate the
    // product's SVD instead (tiny blocks, or a dense update of a low-rank block)
    std::vector<double> P(m * n, 0.0);  // column-major product
    for (int l = 0; l < k; ++l)
      for (int64_t j = 0; j < n; ++j) {
        const double v = V[l * n + j];
        if (v == 0.0) continue;
        for (int64_t i = 0; i < m; ++i) P[j * m + i] += U[l * m + i] * v;
      }
    dense_lowrank(P, m, n, eps, abs_tol, lapack, U, V, k);
    return;
  }
  int im = static_cast<int>(m), in = static_cast<int>(n), info = 0;
  std::vector<double> tu(k), tv(k), work(1);
  int lwork = -1;
  double wq = 0.0;
  lapack.dgeqrf(&im, &k, U.data(), &im, tu.data(), &wq, &lwork, &info);
  lwork = std::max(static_cast<int>(wq), static_cast<int>(std::max(m, n)) * 64);
  work.resize(lwork);
  lapack.dgeqrf(&im, &k, U.data(), &im, tu.data(), work.data(), &lwork, &info);
  if (info) throw std::runtime_error("H-LU: dgeqrf failed");
  lapack.dgeqrf(&in, &k, V.data(), &in, tv.data(), work.data(), &lwork, &info);
  if (info) throw std::runtime_error("H-LU: dgeqrf failed");
  std::vector<double> core(static_cast<size_t>(k) * k, 0.0);  // Ru Rv^T, column-major
  for (int j = 0; j < k; ++j)
    for (int i = 0; i < k; ++i) {
      double acc = 0.0;
      for (int l = std::max(i, j); l < k; ++l) acc += U[l * m + i] * V[l * n + j];
      core[j * k + i] = acc;
    }
  std::vector<double> sv(k), Wm(static_cast<size_t>(k) * k), Zt(static_cast<size_t>(k) * k);
  core_svd(core.data(), k, sv.data(), Wm.data(), Zt.data(), lapack);
  int r = static_cast<int>(truncation_rank(sv.data(), k, eps, abs_tol));
  if (r == 0) {  // the product is zero to eps of itself (or exactly zero)
    U.clear();
    V.clear();
    k = 0;
    return;
  }
  std::vector<double> nu(m * r, 0.0), nv(n * r, 0.0);
  for (int j = 0; j < r; ++j)
    for (int i = 0; i < k; ++i) {
      nu[j * m + i] = Wm[j * k + i] * sv[j];
      nv[j * n + i] = Zt[i * k + j];
    }
  char side = 'L', trans = 'N';
  lapack.dormqr(&side, &trans, &im, &r, &k, U.data(), &im, tu.data(), nu.data(), &im,
                work.data(), &lwork, &info);
  if (info) throw std::runtime_error("H-LU: dormqr failed");
  lapack.dormqr(&side, &trans, &in, &r, &k, V.data(), &in, tv.data(), nv.data(), &in,
                work.data(), &lwork, &info);
  if (info) throw std::runtime_error("H-LU: dormqr failed");
  U.swap(nu);
  V.swap(nv);
  k = r;
}

}  // namespace bemcontact
