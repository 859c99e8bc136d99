// H-LU factorization in hierarchical-matrix arithmetic (see hlu.hpp).
#include "hmat/hlu.hpp"
#include "la/lowrank.hpp"
#include "parallel.hpp"

#include <algorithm>
#include <chrono>
#include <cstring>
#include <exception>
#include <stdexcept>

namespace bemcontact {

// ------------------------------------------------------------------ nodes

enum Kind { kFull = 0, kRk = 1, kH = 2 };

struct HNode {
  int tau = 0, sigma = 0;
  int64_t r0 = 0, c0 = 0;  // first row / column (permuted dof order)
  int64_t m = 0, n = 0;    // rows, columns
  int kind = kFull;
  std::vector<double> A;     // full: column-major m x n
  std::vector<double> U, V;  // rk: m x k and n x k, column-major
  int k = 0;
  std::vector<int> piv;  // full diagonal leaf after LU: LAPACK pivots (1-based)
  std::unique_ptr<HNode> ch[4];
  HNode& c(int i, int j) { return *ch[2 * i + j]; }
  const HNode& c(int i, int j) const { return *ch[2 * i + j]; }
};

namespace {

// column-major view
struct Mat {
  double* p;
  int64_t m, n, ld;
  Mat rows(int64_t r, int64_t mm) const { return {p + r, mm, n, ld}; }
  Mat cols(int64_t c, int64_t nn) const { return {p + c * ld, m, nn, ld}; }
};

inline int I(int64_t v) { return static_cast<int>(v); }

}  // namespace

struct HArith {
  const std::vector<HCluster>& cl;
  const Lapack& lapack;
  const Blas& blas;
  double eps;
  // keeps an exception inside the task that raised it (parallel.hpp); the
  // code after each taskwait raises it again
  ExceptionGuard& guard;

  // blocks worth a task of their own (smaller ones run in the calling task)
  static bool big(const HNode& a) { return a.m * a.n >= 300 * 300; }

  void gemm(char ta, char tb, int64_t m, int64_t n, int64_t k, double alpha, const double* a,
            int64_t lda, const double* b, int64_t ldb, double beta, double* c,
            int64_t ldc) const {
    if (m == 0 || n == 0) return;
    if (k == 0) {
      if (beta != 1.0)
        for (int64_t j = 0; j < n; ++j)
          for (int64_t i = 0; i < m; ++i) c[j * ldc + i] *= beta;
      return;
    }
    int im = I(m), in = I(n), ik = I(k), ila = I(std::max<int64_t>(lda, 1)),
        ilb = I(std::max<int64_t>(ldb, 1)), ilc = I(std::max<int64_t>(ldc, 1));
    blas.dgemm(&ta, &tb, &im, &in, &ik, &alpha, const_cast<double*>(a), &ila,
               const_cast<double*>(b), &ilb, &beta, c, &ilc);
  }

  // Y += alpha op(a) X  (op = a or a^T)
  void mult(const HNode& a, char trans, const Mat& X, const Mat& Y, double alpha) const {
    if (X.n == 0) return;
    const bool t = trans == 'T';
    if (a.kind == kFull) {
      gemm(t ? 'T' : 'N', 'N', t ? a.n : a.m, X.n, t ? a.m : a.n, alpha, a.A.data(), a.m, X.p,
           X.ld, 1.0, Y.p, Y.ld);
    } else if (a.kind == kRk) {
      if (a.k == 0) return;
      const double* L = t ? a.V.data() : a.U.data();  // left factor of op(a)
      const double* R = t ? a.U.data() : a.V.data();
      const int64_t lm = t ? a.n : a.m, rm = t ? a.m : a.n;
      std::vector<double> T(static_cast<size_t>(a.k) * X.n);
      gemm('T', 'N', a.k, X.n, rm, 1.0, R, rm, X.p, X.ld, 0.0, T.data(), a.k);
      gemm('N', 'N', lm, X.n, a.k, alpha, L, lm, T.data(), a.k, 1.0, Y.p, Y.ld);
    } else {
      for (int i = 0; i < 2; ++i)
        for (int j = 0; j < 2; ++j) {
          const HNode& s = a.c(i, j);
          const int64_t ro = s.r0 - a.r0, co = s.c0 - a.c0;
          if (!t)
            mult(s, 'N', X.rows(co, s.n), Y.rows(ro, s.m), alpha);
          else
            mult(s, 'T', X.rows(ro, s.m), Y.rows(co, s.n), alpha);
        }
    }
  }

  // Y += alpha X a  (X: Y.m x a.m, Y: Y.m x a.n)
  void mult_right(const Mat& X, const HNode& a, const Mat& Y, double alpha) const {
    if (X.m == 0) return;
    if (a.kind == kFull) {
      gemm('N', 'N', X.m, a.n, a.m, alpha, X.p, X.ld, a.A.data(), a.m, 1.0, Y.p, Y.ld);
    } else if (a.kind == kRk) {
      if (a.k == 0) return;
      std::vector<double> T(static_cast<size_t>(X.m) * a.k);
      gemm('N', 'N', X.m, a.k, a.m, 1.0, X.p, X.ld, a.U.data(), a.m, 0.0, T.data(), X.m);
      gemm('N', 'T', X.m, a.n, a.k, alpha, T.data(), X.m, a.V.data(), a.n, 1.0, Y.p, Y.ld);
    } else {
      for (int i = 0; i < 2; ++i)
        for (int j = 0; j < 2; ++j) {
          const HNode& s = a.c(i, j);
          mult_right(X.cols(s.r0 - a.r0, s.m), s, Y.cols(s.c0 - a.c0, s.n), alpha);
        }
    }
  }

  // low-rank c := [c.U, U'] [c.V, V']^T truncated, where fill(U', V') writes
  // the k new terms (U': c.m x k, V': c.n x k, column-major, zero on entry)
  template <class F>
  void append_terms(HNode& c, int k, F&& fill) const {
    const int nk = c.k + k;
    std::vector<double> nu(c.m * nk), nv(c.n * nk);
    std::copy(c.U.begin(), c.U.end(), nu.begin());
    std::copy(c.V.begin(), c.V.end(), nv.begin());
    fill(nu.data() + c.k * c.m, nv.data() + c.k * c.n);
    c.U.swap(nu);
    c.V.swap(nv);
    c.k = nk;
    truncate_lowrank(c.U, c.V, c.m, c.n, c.k, eps, lapack);
  }

  // c += alpha U V^T (U: c.m x k with leading dimension ldu, V: c.n x k)
  void add_rk(HNode& c, const double* U, int64_t ldu, const double* V, int64_t ldv, int k,
              double alpha) const {
    if (k == 0) return;
    if (c.kind == kFull) {
      gemm('N', 'T', c.m, c.n, k, alpha, U, ldu, V, ldv, 1.0, c.A.data(), c.m);
    } else if (c.kind == kRk) {
      append_terms(c, k, [&](double* nu, double* nv) {
        for (int l = 0; l < k; ++l) {
          for (int64_t i = 0; i < c.m; ++i) nu[l * c.m + i] = alpha * U[l * ldu + i];
          for (int64_t j = 0; j < c.n; ++j) nv[l * c.n + j] = V[l * ldv + j];
        }
      });
    } else {
      for (int i = 0; i < 2; ++i)
        for (int j = 0; j < 2; ++j) {
          HNode& s = c.c(i, j);
          add_rk(s, U + (s.r0 - c.r0), ldu, V + (s.c0 - c.c0), ldv, k, alpha);
        }
    }
  }

  // c += alpha P (P: c.m x c.n)
  void add_dense(HNode& c, const Mat& P, double alpha) const {
    if (c.kind == kFull) {
      for (int64_t j = 0; j < c.n; ++j)
        for (int64_t i = 0; i < c.m; ++i) c.A[j * c.m + i] += alpha * P.p[j * P.ld + i];
    } else if (c.kind == kRk) {
      // c.U c.V^T + alpha P = [c.U, alpha P] [c.V, I]^T, truncated once
      append_terms(c, static_cast<int>(c.n), [&](double* nu, double* nv) {
        for (int64_t j = 0; j < c.n; ++j) {
          for (int64_t i = 0; i < c.m; ++i) nu[j * c.m + i] = alpha * P.p[j * P.ld + i];
          nv[j * c.n + j] = 1.0;
        }
      });
    } else {
      for (int i = 0; i < 2; ++i)
        for (int j = 0; j < 2; ++j) {
          HNode& s = c.c(i, j);
          add_dense(s, P.rows(s.r0 - c.r0, s.m).cols(s.c0 - c.c0, s.n), alpha);
        }
    }
  }

  // a node as a dense column-major matrix
  std::vector<double> dense(const HNode& a) const {
    std::vector<double> D(a.m * a.n, 0.0);
    std::vector<double> E(a.n * a.n, 0.0);
    for (int64_t j = 0; j < a.n; ++j) E[j * a.n + j] = 1.0;
    mult(a, 'N', Mat{E.data(), a.n, a.n, a.n}, Mat{D.data(), a.m, a.n, a.m}, 1.0);
    return D;
  }

  // split a low-rank node into 2 x 2 low-rank children (for an H x H update)
  void split(HNode& c) const {
    const HCluster& t = cl[c.tau];
    const HCluster& s = cl[c.sigma];
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j) {
        auto ch = std::make_unique<HNode>();
        ch->tau = t.child[i];
        ch->sigma = s.child[j];
        ch->r0 = 3 * cl[ch->tau].begin;
        ch->c0 = 3 * cl[ch->sigma].begin;
        ch->m = 3 * cl[ch->tau].size();
        ch->n = 3 * cl[ch->sigma].size();
        ch->kind = kRk;
        ch->k = c.k;
        ch->U.resize(ch->m * c.k);
        ch->V.resize(ch->n * c.k);
        for (int l = 0; l < c.k; ++l) {
          std::memcpy(&ch->U[l * ch->m], &c.U[l * c.m + (ch->r0 - c.r0)], ch->m * sizeof(double));
          std::memcpy(&ch->V[l * ch->n], &c.V[l * c.n + (ch->c0 - c.c0)], ch->n * sizeof(double));
        }
        c.ch[2 * i + j] = std::move(ch);
      }
    c.kind = kH;
    c.U.clear();
    c.V.clear();
    c.k = 0;
  }

  // merge 2 x 2 low-rank children back into one truncated low-rank node
  void merge(HNode& c) const {
    int K = 0;
    for (int q = 0; q < 4; ++q) {
      if (c.ch[q]->kind == kH) merge(*c.ch[q]);
      if (c.ch[q]->kind == kFull) {  // (not produced by split; kept general)
        HNode& s = *c.ch[q];
        std::vector<double> U(s.A), V(s.n * s.n, 0.0);
        for (int64_t j = 0; j < s.n; ++j) V[j * s.n + j] = 1.0;
        int k = static_cast<int>(s.n);
        truncate_lowrank(U, V, s.m, s.n, k, eps, lapack);
        s.kind = kRk;
        s.U.swap(U);
        s.V.swap(V);
        s.k = k;
        s.A.clear();
      }
      K += c.ch[q]->k;
    }
    std::vector<double> U(c.m * K, 0.0), V(c.n * K, 0.0);
    int off = 0;
    for (int q = 0; q < 4; ++q) {
      const HNode& s = *c.ch[q];
      for (int l = 0; l < s.k; ++l) {
        std::memcpy(&U[(off + l) * c.m + (s.r0 - c.r0)], &s.U[l * s.m], s.m * sizeof(double));
        std::memcpy(&V[(off + l) * c.n + (s.c0 - c.c0)], &s.V[l * s.n], s.n * sizeof(double));
      }
      off += s.k;
    }
    for (auto& p : c.ch) p.reset();
    c.kind = kRk;
    c.U.swap(U);
    c.V.swap(V);
    c.k = K;
    truncate_lowrank(c.U, c.V, c.m, c.n, c.k, eps, lapack);
  }

  // c += alpha a b
  void gemm_node(HNode& c, const HNode& a, const HNode& b, double alpha) const {
    if (a.kind == kRk) {
      if (a.k == 0) return;
      std::vector<double> W(b.n * a.k, 0.0);  // b^T a.V
      mult(b, 'T', Mat{const_cast<double*>(a.V.data()), a.n, a.k, a.n},
           Mat{W.data(), b.n, a.k, b.n}, 1.0);
      add_rk(c, a.U.data(), a.m, W.data(), b.n, a.k, alpha);
    } else if (b.kind == kRk) {
      if (b.k == 0) return;
      std::vector<double> Z(a.m * b.k, 0.0);  // a b.U
      mult(a, 'N', Mat{const_cast<double*>(b.U.data()), b.m, b.k, b.m},
           Mat{Z.data(), a.m, b.k, a.m}, 1.0);
      add_rk(c, Z.data(), a.m, b.V.data(), b.n, b.k, alpha);
    } else if (a.kind == kH && b.kind == kH) {
      if (c.kind == kRk) {
        split(c);
        gemm_node(c, a, b, alpha);
        merge(c);
      } else if (c.kind == kH) {
        // the four target blocks are disjoint: one task each (large blocks)
        const bool par = big(c);
        for (int i = 0; i < 2; ++i)
          for (int j = 0; j < 2; ++j) {
#pragma omp task if (par) default(shared) firstprivate(i, j)
            guard.run([&] {
              for (int l = 0; l < 2; ++l) gemm_node(c.c(i, j), a.c(i, l), b.c(l, j), alpha);
            });
          }
#pragma omp taskwait
        guard.rethrow();
      } else {
        std::vector<double> Bd = dense(b), P(a.m * b.n, 0.0);
        mult(a, 'N', Mat{Bd.data(), b.m, b.n, b.m}, Mat{P.data(), a.m, b.n, a.m}, 1.0);
        add_dense(c, Mat{P.data(), a.m, b.n, a.m}, alpha);
      }
    } else if (b.kind == kFull) {  // a full or H
      std::vector<double> P(a.m * b.n, 0.0);
      mult(a, 'N', Mat{const_cast<double*>(b.A.data()), b.m, b.n, b.m},
           Mat{P.data(), a.m, b.n, a.m}, 1.0);
      add_dense(c, Mat{P.data(), a.m, b.n, a.m}, alpha);
    } else {  // a full, b H
      std::vector<double> P(a.m * b.n, 0.0);
      mult_right(Mat{const_cast<double*>(a.A.data()), a.m, a.n, a.m}, b,
                 Mat{P.data(), a.m, b.n, a.m}, 1.0);
      add_dense(c, Mat{P.data(), a.m, b.n, a.m}, alpha);
    }
  }

  // B := op(T)^{-1} B (side L) or B T^{-1} (side R) with T the lower
  // (uplo L) or upper (U) triangle of the factored dense diagonal leaf d
  // (diag U: unit diagonal)
  void trsm_leaf(char side, char uplo, char diag, const HNode& d, const Mat& B) const {
    char tr = 'N';
    int m = I(B.m), n = I(B.n), lda = I(d.m), ld = I(B.ld);
    double one = 1.0;
    blas.dtrsm(&side, &uplo, &tr, &diag, &m, &n, &one, const_cast<double*>(d.A.data()), &lda,
               B.p, &ld);
  }

  // B := L^{-1} P B (L: unit lower factor of diagonal node d, P its pivots)
  void solve_lower(const HNode& d, const Mat& B) const {
    if (B.n == 0) return;
    if (d.kind == kFull) {
      int n = I(B.n), ld = I(B.ld), k1 = 1, k2 = I(d.m), inc = 1;
      blas.dlaswp(&n, B.p, &ld, &k1, &k2, const_cast<int*>(d.piv.data()), &inc);
      trsm_leaf('L', 'L', 'U', d, B);
      return;
    }
    const HNode& d11 = d.c(0, 0);
    const int64_t m1 = d11.m;
    solve_lower(d11, B.rows(0, m1));
    mult(d.c(1, 0), 'N', B.rows(0, m1), B.rows(m1, B.m - m1), -1.0);
    solve_lower(d.c(1, 1), B.rows(m1, B.m - m1));
  }

  // B := U^{-1} B
  void solve_upper(const HNode& d, const Mat& B) const {
    if (B.n == 0) return;
    if (d.kind == kFull) {
      trsm_leaf('L', 'U', 'N', d, B);
      return;
    }
    const int64_t m1 = d.c(0, 0).m;
    solve_upper(d.c(1, 1), B.rows(m1, B.m - m1));
    mult(d.c(0, 1), 'N', B.rows(m1, B.m - m1), B.rows(0, m1), -1.0);
    solve_upper(d.c(0, 0), B.rows(0, m1));
  }

  // X := X U^{-1} (X: X.m x d.n)
  void solve_upper_right(const HNode& d, const Mat& X) const {
    if (X.m == 0) return;
    if (d.kind == kFull) {
      trsm_leaf('R', 'U', 'N', d, X);
      return;
    }
    const int64_t n1 = d.c(0, 0).n;
    solve_upper_right(d.c(0, 0), X.cols(0, n1));
    mult_right(X.cols(0, n1), d.c(0, 1), X.cols(n1, X.n - n1), -1.0);
    solve_upper_right(d.c(1, 1), X.cols(n1, X.n - n1));
  }

  // x := L^{-1} P x for a block row node x (rows of the diagonal node d)
  void trsm_lower(const HNode& d, HNode& x) const {
    if (x.kind == kFull) {
      solve_lower(d, Mat{x.A.data(), x.m, x.n, x.m});
    } else if (x.kind == kRk) {
      if (x.k) solve_lower(d, Mat{x.U.data(), x.m, x.k, x.m});
    } else {
      if (d.kind != kH) throw std::logic_error("H-LU: block structure mismatch (lower)");
      const bool par = big(x);
      for (int j = 0; j < 2; ++j) {  // the two block columns are independent
#pragma omp task if (par) default(shared) firstprivate(j)
        guard.run([&] {
          trsm_lower(d.c(0, 0), x.c(0, j));
          gemm_node(x.c(1, j), d.c(1, 0), x.c(0, j), -1.0);
          trsm_lower(d.c(1, 1), x.c(1, j));
        });
      }
#pragma omp taskwait
      guard.rethrow();
    }
  }

  // x := x U^{-1} for a block column node x (columns of the diagonal node d)
  void trsm_upper_right(const HNode& d, HNode& x) const {
    if (x.kind == kFull) {
      solve_upper_right(d, Mat{x.A.data(), x.m, x.n, x.m});
    } else if (x.kind == kRk) {
      if (!x.k) return;
      // (U V^T) U_d^{-1} = U (V^T U_d^{-1}): solve on V^T (k x n)
      std::vector<double> Vt(static_cast<size_t>(x.k) * x.n);
      for (int l = 0; l < x.k; ++l)
        for (int64_t j = 0; j < x.n; ++j) Vt[j * x.k + l] = x.V[l * x.n + j];
      solve_upper_right(d, Mat{Vt.data(), x.k, x.n, x.k});
      for (int l = 0; l < x.k; ++l)
        for (int64_t j = 0; j < x.n; ++j) x.V[l * x.n + j] = Vt[j * x.k + l];
    } else {
      if (d.kind != kH) throw std::logic_error("H-LU: block structure mismatch (upper)");
      const bool par = big(x);
      for (int i = 0; i < 2; ++i) {  // the two block rows are independent
#pragma omp task if (par) default(shared) firstprivate(i)
        guard.run([&] {
          trsm_upper_right(d.c(0, 0), x.c(i, 0));
          gemm_node(x.c(i, 1), x.c(i, 0), d.c(0, 1), -1.0);
          trsm_upper_right(d.c(1, 1), x.c(i, 1));
        });
      }
#pragma omp taskwait
      guard.rethrow();
    }
  }
};

// ------------------------------------------------------------------ HLU

HLU::~HLU() = default;

std::unique_ptr<HNode> HLU::build(int tau, int sigma, const HMatrix& h,
                                  const std::vector<int64_t>& index) {
  auto node = std::make_unique<HNode>();
  node->tau = tau;
  node->sigma = sigma;
  const HCluster& t = clusters_[tau];
  const HCluster& s = clusters_[sigma];
  node->r0 = 3 * t.begin;
  node->c0 = 3 * s.begin;
  node->m = 3 * t.size();
  node->n = 3 * s.size();
  const int64_t key = static_cast<int64_t>(tau) * static_cast<int64_t>(clusters_.size()) + sigma;
  const int64_t bi = index[key];
  if (bi >= 0) {
    const HBlock& b = h.blocks()[bi];
    if (b.rank < 0) {
      node->kind = kFull;
      node->A.resize(node->m * node->n);
      for (int64_t i = 0; i < node->m; ++i)
        for (int64_t j = 0; j < node->n; ++j) node->A[j * node->m + i] = b.A[i * node->n + j];
    } else {
      node->kind = kRk;
      node->k = b.rank;
      b.factors(node->U, node->V, node->m, node->n);
    }
    leaves_.push_back(node.get());
    return node;
  }
  if (t.leaf() || s.leaf()) throw std::logic_error("H-LU: missing leaf block");
  node->kind = kH;
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j) node->ch[2 * i + j] = build(t.child[i], s.child[j], h, index);
  return node;
}

void HLU::lu(HNode& a, ExceptionGuard& guard) const {
  HArith ar{clusters_, lapack_, blas_, eps_, guard};
  if (a.kind == kFull) {
    int m = I(a.m), info = 0;
    a.piv.resize(a.m);
    blas_.dgetrf(&m, &m, a.A.data(), &m, a.piv.data(), &info);
    if (info > 0)
      throw std::runtime_error("H-LU: exactly singular pivot in a diagonal block (is the body "
                               "free to move? free rigid modes need the dense path)");
    if (info < 0) throw std::runtime_error("H-LU: dgetrf argument error");
    return;
  }
  if (a.kind != kH) throw std::logic_error("H-LU: a diagonal block is low rank");
  lu(a.c(0, 0), guard);
  const bool par = HArith::big(a.c(0, 1));
#pragma omp task if (par) default(shared)
  guard.run([&] { ar.trsm_lower(a.c(0, 0), a.c(0, 1)); });
#pragma omp task if (par) default(shared)
  guard.run([&] { ar.trsm_upper_right(a.c(0, 0), a.c(1, 0)); });
#pragma omp taskwait
  guard.rethrow();
  ar.gemm_node(a.c(1, 1), a.c(1, 0), a.c(0, 1), -1.0);
  lu(a.c(1, 1), guard);
}

HLU::HLU(const HMatrix& h, const Lapack& lapack, const Blas& blas, double eps,
         const double* U, const double* V, int64_t r, int threads)
    : n_(h.n_points()), perm_(h.perm()), clusters_(h.clusters()), lapack_(lapack), blas_(blas),
      eps_(eps) {
  if (!lapack_.ok() || !blas_.ok()) throw std::invalid_argument("H-LU needs BLAS and LAPACK");
  const auto t0 = std::chrono::steady_clock::now();
  const int64_t nc = static_cast<int64_t>(clusters_.size());
  std::vector<int64_t> index(nc * nc, -1);
  for (size_t b = 0; b < h.blocks().size(); ++b) {
    const HBlock& blk = h.blocks()[b];
    index[static_cast<int64_t>(blk.tau) * nc + blk.sigma] = static_cast<int64_t>(b);
  }
  root_ = build(0, 0, h, index);
  // The blocks were compressed to the H-matrix's eps; a looser factorization
  // (a coarse preconditioner) first truncates them to its own eps, so the
  // updates below work on the smaller ranks.
  if (eps_ > h.params().eps) {
    ExceptionGuard guard;
#pragma omp parallel for schedule(dynamic, 4) num_threads(std::max(threads, 1))
    for (int64_t q = 0; q < static_cast<int64_t>(leaves_.size()); ++q) {
      HNode& a = *leaves_[q];
      guard.run([&] {
        if (a.kind == kRk) truncate_lowrank(a.U, a.V, a.m, a.n, a.k, eps_, lapack_);
      });
    }
    guard.rethrow();
  }
  leaves_.clear();
  leaves_.shrink_to_fit();
  if (r > 0) {
    const int64_t n3 = 3 * n_;
    std::vector<double> up(n3 * r), vp(n3 * r);  // permuted order, column-major
    for (int64_t p = 0; p < n_; ++p)
      for (int c = 0; c < 3; ++c)
        for (int64_t l = 0; l < r; ++l) {
          up[l * n3 + 3 * p + c] = U[(3 * perm_[p] + c) * r + l];
          vp[l * n3 + 3 * p + c] = V[(3 * perm_[p] + c) * r + l];
        }
    ExceptionGuard guard;
    HArith ar{clusters_, lapack_, blas_, eps_, guard};
    ar.add_rk(*root_, up.data(), n3, vp.data(), n3, static_cast<int>(r), 1.0);
  }
  ExceptionGuard guard;
#pragma omp parallel num_threads(std::max(threads, 1))
#pragma omp single
  guard.run([&] { lu(*root_, guard); });
  guard.rethrow();
  factor_s_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void HLU::solve(double* b, int64_t k) const {
  const int64_t n3 = 3 * n_;
  std::vector<double> w(n3 * k);  // permuted order, column-major
  for (int64_t p = 0; p < n_; ++p)
    for (int c = 0; c < 3; ++c) {
      const double* src = b + (3 * perm_[p] + c) * k;
      for (int64_t q = 0; q < k; ++q) w[q * n3 + 3 * p + c] = src[q];
    }
  ExceptionGuard guard;
  HArith ar{clusters_, lapack_, blas_, eps_, guard};
  const Mat W{w.data(), n3, k, n3};
  ar.solve_lower(*root_, W);
  ar.solve_upper(*root_, W);
  for (int64_t p = 0; p < n_; ++p)
    for (int c = 0; c < 3; ++c) {
      double* dst = b + (3 * perm_[p] + c) * k;
      for (int64_t q = 0; q < k; ++q) dst[q] = w[q * n3 + 3 * p + c];
    }
}

namespace {
void count(const HNode& a, int64_t& s, int& r) {
  if (a.kind == kH) {
    for (const auto& c : a.ch) count(*c, s, r);
    return;
  }
  s += static_cast<int64_t>(a.A.size() + a.U.size() + a.V.size());
  if (a.kind == kRk) r = std::max(r, a.k);
}
}  // namespace

int64_t HLU::stored_doubles() const {
  int64_t s = 0;
  int r = 0;
  count(*root_, s, r);
  return s;
}

int HLU::max_rank() const {
  int64_t s = 0;
  int r = 0;
  count(*root_, s, r);
  return r;
}

}  // namespace bemcontact
