// Hierarchical-matrix (H-matrix) form of a body's mixed BEM system matrix
// A (H on traction-given columns, -G on displacement-given ones): a cluster tree on the functional nodes (3 unknowns per node kept
// together), standard admissibility on the bounding boxes of the nodes'
// element supports, low-rank blocks by adaptive cross approximation (ACA
// with partial pivoting and random residual checks, on [H | s G] together),
// dense near-field blocks.  Built straight from element integrals, never
// from a dense matrix.  The companion matrix B (G on traction-given columns,
// -H on displacement-given ones; b = B * boundary values) is applied to a
// given block of vectors W during the build and never stored.  Low-rank
// blocks of A are recompressed (QR + SVD, LAPACK from SciPy) to A's own rank.
//
// Sources: the build in hmatrix.cpp, the cluster tree in cluster.{hpp,cpp},
// node rows, node columns and entries from the element integrals in
// entries.cpp, the low-rank blocks in aca.cpp, the products in apply.cpp.
#pragma once

#include <cstdint>
#include <unordered_map>
#include <vector>

#include "bem/integration.hpp"
#include "hmat/cluster.hpp"
#include "la/lapack.hpp"

namespace bemcontact {

struct HParams {
  double eps = 1e-6;     // relative accuracy of each low-rank block (Frobenius)
  double eta = 3.0;      // admissibility: min(diam) <= eta * dist
  int leaf_size = 48;    // nodes per leaf cluster (at most)
  int max_rank = 0;      // 0: no cap
  int checks = 3;        // random residual rows/columns tested after ACA stops
  // false: each low-rank block to eps of its own norm; true: to an absolute
  // share of eps times the whole matrix's Frobenius norm (estimated from
  // sampled rows), eps sqrt(m n) times the root-mean-square entry, so that
  // the squared block errors sum to at most eps^2 ||[H, G]||_F^2 and blocks
  // of small entries (far apart) keep a lower rank
  bool global = false;
  // store the trailing terms of low-rank blocks in single (2^-24) and half
  // (2^-11 relative rounding) precision where their rounding costs at most
  // half the block's budget
  bool mixed = false;
  int norm_samples = 64;  // nodes whose rows estimate the norms (global)
};

using half = _Float16;
// (through float: half <-> float is one instruction with F16C; the hot
// product converts whole columns to float first, apply.cpp)
inline double to_double(half x) { return static_cast<double>(static_cast<float>(x)); }
inline half to_half(double x) { return static_cast<half>(static_cast<float>(x)); }

struct HBlock {
  int tau = 0, sigma = 0;  // row and column clusters
  int rank = -1;           // -1: dense
  // dense: A row-major (3|tau|) x (3|sigma|); low rank: U (3|tau| x k),
  // V (3|sigma| x k), column l contiguous, block = U V^T.  Mixed precision:
  // the first kd terms in double (U, V), the next kf in float (Uf, Vf), the
  // last rank - kd - kf in half precision (Uh, Vh: each column divided by its
  // largest magnitude, kept in sh as u-scale, v-scale pairs, so that the
  // narrow half exponent range holds it).  A term goes to a lower precision
  // when its rounding fits the block's error budget (aca.cpp, fill_aca).
  std::vector<double> A, U, V;
  std::vector<float> Uf, Vf;
  std::vector<half> Uh, Vh;
  std::vector<double> sh;
  int kd = 0, kf = 0;
  int aca_rank = 0;  // rank found by ACA on [H | s G] (before recompression)
  int aca_checks_failed = 0;
  int kh() const { return rank - kd - kf; }
  // all rank terms in double: U (m x rank), V (n x rank)
  void factors(std::vector<double>& u, std::vector<double>& v, int64_t m, int64_t n) const {
    u.assign(U.begin(), U.begin() + m * kd);
    v.assign(V.begin(), V.begin() + n * kd);
    u.insert(u.end(), Uf.begin(), Uf.end());
    v.insert(v.end(), Vf.begin(), Vf.end());
    for (int l = 0; l < kh(); ++l) {
      for (int64_t i = 0; i < m; ++i) u.push_back(to_double(Uh[l * m + i]) * sh[2 * l]);
      for (int64_t j = 0; j < n; ++j)
        v.push_back(to_double(Vh[l * n + j]) * sh[2 * l + 1]);
    }
  }
  int64_t stored_bytes() const {
    return static_cast<int64_t>(sizeof(double) * (A.size() + U.size() + V.size() + sh.size()) +
                                sizeof(float) * (Uf.size() + Vf.size()) +
                                sizeof(half) * (Uh.size() + Vh.size()));
  }
};

class HMatrix {
 public:
  // known_u: (3N) 1 where the displacement is given; W: (3N x s) row-major
  // vectors to multiply by B during the build (s may be 0).
  HMatrix(const MeshView& m, const double* points, int64_t n_points, double shear_modulus,
          double nu, const QuadratureParams& q, const HParams& hp, const uint8_t* known_u,
          const double* W, int64_t s, const Lapack& lapack, int threads);

  const HParams& params() const { return hp_; }
  int64_t n_points() const { return n_; }
  // y (3N x k, row-major, original dof order) = A x
  void apply(const double* x, double* y, int64_t k, int threads) const;
  const std::vector<double>& bw() const { return bw_; }  // B W, (3N x s) original order
  int64_t bw_columns() const { return s_; }
  // exact entries of H and G: rows and columns are original dof indices (sizes
  // nr, nc): out_h, out_g row-major nr x nc from element integrals, with the
  // rigid-body diagonal of H (from the compressed row sums).
  void entries(const int64_t* rows, int64_t nr, const int64_t* cols, int64_t nc, double* out_h,
               double* out_g) const;

  // columns `cols` (original dof indices, nc of them) of G over all rows, by
  // element integrals: out is 3N x nc, row-major, original row order.  Each
  // element touching a requested column is integrated once per row.
  void g_columns(const int64_t* cols, int64_t nc, double* out, int threads) const;

  const std::vector<HCluster>& clusters() const { return clusters_; }
  const std::vector<HBlock>& blocks() const { return blocks_; }
  const std::vector<int64_t>& perm() const { return perm_; }  // permuted -> original node
  int64_t stored_bytes() const;
  double build_seconds() const { return build_s_; }
  double rms_h() const { return rms_h_; }
  double rms_g() const { return rms_g_; }
  // thread-seconds spent filling dense and low-rank blocks; element integrals
  // evaluated for node rows and node columns
  double dense_seconds() const { return dense_s_; }
  double aca_seconds() const { return aca_s_; }
  int64_t row_integrals() const { return row_integrals_; }
  int64_t col_integrals() const { return col_integrals_; }

 private:
  // the build, in this order (hmatrix.cpp): functional node -> elements
  // (n2e_ptr_, n2e_); the support box (lo, hi: N x 3) of every node; the
  // cluster tree (cluster.hpp); points, known_u and W in the permuted order;
  // the block partition; every block filled (in parallel), their B W rows and
  // H row sums added up in bw and rs (permuted order); the rigid-body diagonal
  // of H from rs into A or bw
  void index_node_elements();
  void support_boxes(const double* points, std::vector<double>& lo,
                     std::vector<double>& hi) const;
  void permute_inputs(const double* points, const uint8_t* known_u, const double* W);
  void build_blocks(int tau, int sigma, double eta);
  void fill_blocks(int threads, std::vector<double>& bw, std::vector<double>& rs);
  void add_rigid_diagonal(const std::vector<double>& rs, std::vector<double>& bw);
  // element integrals (entries.cpp): 3 rows (node p in permuted order) of
  // [H | G] restricted to cluster sigma's columns: out is 3 x (6 |sigma|), H
  // columns first.
  void node_rows(int64_t p, const HCluster& sigma, const std::vector<int64_t>& elems,
                 double* out) const;
  // 3 columns (node q, permuted) of H and of G over cluster tau's rows: out
  // is (3 |tau|) x 6 row-major (H comps 0..2, then G comps 0..2).
  // With `cache`, each element's influence on tau is computed once and kept.
  void node_cols(int64_t q, const HCluster& tau, double* out,
                 std::unordered_map<int64_t, std::vector<double>>* cache = nullptr) const;
  // fill block b; add its B W rows to bw and its H row sums to rs (both in
  // permuted order, thread-private)
  void fill_dense(HBlock& b, double* bw, double* rs) const;
  void fill_aca(HBlock& b, uint64_t seed, double* bw, double* rs) const;
  struct Aca;  // one block's cross approximation (aca.cpp)
  // (truncation relative to the block norm; callers scale columns to one unit)
  void recompress(HBlock& b, int64_t m, int64_t n, double abs_tol = 0.0) const;
  // the elements touching the nodes of c (entries.cpp)
  std::vector<int64_t> support_elements(const HCluster& c) const;

  int64_t n_ = 0;
  std::vector<double> pts_;  // permuted points (N x 3)
  std::vector<Element> els_;
  Kelvin K_;
  QuadratureParams q_;
  HParams hp_;
  Lapack lapack_;
  double mu_ = 1.0;
  std::vector<uint8_t> ku_;  // permuted dof order
  std::vector<double> w_;    // W in permuted dof order (during the build)
  int64_t s_ = 0;
  std::vector<int64_t> perm_, pos_;     // permuted->original, original->permuted
  std::vector<int64_t> n2e_ptr_, n2e_;  // functional node (original) -> elements
  std::vector<HCluster> clusters_;
  std::vector<HBlock> blocks_;
  std::vector<double> diag_;  // rigid-body diagonal of H: (N x 3 x 3), permuted order
  std::vector<double> bw_;    // B W, original order
  // root-mean-square entries of H and G (global truncation; 0 otherwise)
  double rms_h_ = 0.0, rms_g_ = 0.0;
  void estimate_norms(int threads);
  // absolute error budget of a low-rank block of [H | s G] (0: relative only)
  double block_budget(int64_t m, int64_t n, double scale) const;
  double build_s_ = 0.0;
  double dense_s_ = 0.0, aca_s_ = 0.0;
  mutable int64_t row_integrals_ = 0, col_integrals_ = 0;
};

}  // namespace bemcontact
