// Low-rank blocks of the H-matrix (see hmatrix.hpp): adaptive cross
// approximation of [H | s G] (HMatrix::Aca), the block's factors of A with
// their H row sums and B W, recompression and mixed-precision storage.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <unordered_map>
#include <vector>

#include "hmat/hmatrix.hpp"
#include "la/dot.hpp"
#include "la/lowrank.hpp"

namespace bemcontact {

namespace {

inline uint64_t splitmix(uint64_t& s) {
  uint64_t z = (s += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

}  // namespace

// ACA with partial pivoting on M = [H | s G] (m = 3|tau| rows, n = 6|sigma|
// columns; s = 2 mu / distance puts both parts on one scale), pivoting by
// *node*: all three rows of a pivot node are eliminated before moving on.
// This matters for elasticity: for coplanar clusters the kernels decouple
// (G has no in-plane/normal coupling, H only that coupling), and scalar
// partial pivoting can stay inside one decoupled part and stop with another
// part untouched.  When a node brings no significant update the iteration
// would stop; random unused node rows and node columns are then checked
// against the approximation (the guard ACA+ gets from its reference row and
// column), and a residual above the whole block's error budget restarts the
// iteration at that node.
struct HMatrix::Aca {
  const HMatrix& h;
  HBlock& b;
  const HCluster& tau;
  const HCluster& sig;
  const int64_t m, nH, n;   // rows, H columns, columns of M (H and G)
  const double scale;       // s
  const double budget_abs;  // absolute error budget (global truncation; else 0)
  const int64_t maxk;       // rank limit (beyond it the block is stored dense)
  const std::vector<int64_t> elems;  // elements touching sigma's nodes
  // node rows (3 x n) and node columns (m x 6) computed so far: one element
  // integration serves the three components (and H and G) at once
  std::vector<std::vector<double>> row_cache, col_cache;
  std::unordered_map<int64_t, std::vector<double>> elem_cache;
  std::vector<std::vector<double>> U, V;  // the terms u_l v_l^T found
  std::vector<char> row_used, col_used, node_done;
  uint64_t rng;
  double norm2 = 0.0;  // of the approximation (see update_norm)
  std::vector<double> r, u, last_u;
  int rounds = 0;  // residual checks made

  Aca(const HMatrix& h, HBlock& b, uint64_t seed);
  static int64_t rank_limit(int64_t m, int64_t n, int max_rank);
  void get_row(int64_t i, std::vector<double>& out);
  void get_col(int64_t j, std::vector<double>& out);
  template <class F>
  int64_t random_index(int64_t len, F&& usable);
  int64_t pivot_column(const std::vector<double>& row) const;
  int64_t largest_open_node(const std::vector<double>& col) const;
  void update_norm(double uu, double vv);
  bool step(int64_t i);
  int64_t check_residuals();
  bool run();
  void store(double* bw, double* rs) const;
};

HMatrix::Aca::Aca(const HMatrix& h, HBlock& b, uint64_t seed)
    : h(h),
      b(b),
      tau(h.clusters_[b.tau]),
      sig(h.clusters_[b.sigma]),
      m(3 * tau.size()),
      nH(3 * sig.size()),
      n(2 * nH),
      scale(2.0 * h.mu_ / std::max(center_dist(tau, sig), 1e-300)),
      budget_abs(h.block_budget(m, nH, scale)),
      maxk(rank_limit(m, n, h.hp_.max_rank)),
      elems(h.support_elements(sig)),
      row_cache(tau.size()),
      col_cache(sig.size()),
      row_used(m, 0),
      col_used(n, 0),
      node_done(tau.size(), 0),
      rng(seed) {}

int64_t HMatrix::Aca::rank_limit(int64_t m, int64_t n, int max_rank) {
  int64_t maxk = std::min(m, n);
  if (max_rank > 0) maxk = std::min<int64_t>(maxk, max_rank);
  // dense is cheaper to store beyond this rank
  return std::min(maxk, (m * n) / (m + n) + 1);
}

// Row i of the residual M - sum_l u_l v_l^T, into out.
void HMatrix::Aca::get_row(int64_t i, std::vector<double>& out) {
  const int64_t p = i / 3;
  std::vector<double>& cached = row_cache[p];
  if (cached.empty()) {
    cached.resize(3 * n);
    h.node_rows(tau.begin + p, sig, elems, cached.data());
  }
  const double* src = cached.data() + (i % 3) * n;
  out.assign(src, src + n);
  for (int64_t c = nH; c < n; ++c) out[c] *= scale;
  for (size_t l = 0; l < U.size(); ++l) {
    const double a = U[l][i];
    const double* v = V[l].data();
    for (int64_t c = 0; c < n; ++c) out[c] -= a * v[c];
  }
}

// Column j of the residual, into out.
void HMatrix::Aca::get_col(int64_t j, std::vector<double>& out) {
  const int64_t jj = j % nH;
  const int64_t qn = jj / 3;
  std::vector<double>& colbuf = col_cache[qn];
  if (colbuf.empty()) {
    colbuf.resize(m * 6);
    h.node_cols(sig.begin + qn, tau, colbuf.data(), &elem_cache);
  }
  const bool g = j >= nH;
  const int comp = static_cast<int>(jj % 3) + (g ? 3 : 0);
  const double f = g ? scale : 1.0;
  out.resize(m);
  for (int64_t t = 0; t < m; ++t) out[t] = colbuf[t * 6 + comp] * f;
  for (size_t l = 0; l < U.size(); ++l) {
    const double a = V[l][j];
    const double* w = U[l].data();
    for (int64_t t = 0; t < m; ++t) out[t] -= a * w[t];
  }
}

// A random t in [0, len) with usable(t), -1 if there is none.
template <class F>
int64_t HMatrix::Aca::random_index(int64_t len, F&& usable) {
  int64_t cnt = 0;
  for (int64_t t = 0; t < len; ++t) cnt += usable(t);
  if (!cnt) return -1;
  int64_t k = static_cast<int64_t>(splitmix(rng) % static_cast<uint64_t>(cnt));
  for (int64_t t = 0; t < len; ++t)
    if (usable(t) && k-- == 0) return t;
  return -1;
}

// The pivot of a residual row: its largest entry in an unused column (-1 if
// there is none above 1e-300).
int64_t HMatrix::Aca::pivot_column(const std::vector<double>& row) const {
  int64_t j = -1;
  double best = 0.0;
  for (int64_t c = 0; c < n; ++c)
    if (!col_used[c] && std::fabs(row[c]) > best) {
      best = std::fabs(row[c]);
      j = c;
    }
  return best <= 1e-300 ? -1 : j;
}

// The next pivot node from a residual column: the node, not yet done, of its
// largest entry (-1 if every node is done).
int64_t HMatrix::Aca::largest_open_node(const std::vector<double>& col) const {
  int64_t next = -1;
  double bu = -1.0;
  for (int64_t t = 0; t < m; ++t)
    if (!node_done[t / 3] && std::fabs(col[t]) > bu) {
      bu = std::fabs(col[t]);
      next = t / 3;
    }
  return next;
}

// norm2 += the new term u r^T (uu = |u|^2, vv = |r|^2).  norm2 is a lower
// bound of |S_k|_F^2 (exact while the terms are large): the exact update costs
// a pass over all previous terms (the k^2 (m + n) part of the ACA); once a
// term is below 1e-3 |S| the triangle inequality |S_k| >= |S_{k-1}| - |u||v|
// keeps a lower bound instead, which only makes the stopping test in step
// stricter.
void HMatrix::Aca::update_norm(double uu, double vv) {
  if (uu * vv > 1e-6 * norm2) {
    for (size_t l = 0; l < U.size(); ++l)
      norm2 += 2.0 * dot(U[l].data(), u.data(), m) * dot(V[l].data(), r.data(), n);
    norm2 += uu * vv;
  } else {
    const double low = std::max(std::sqrt(norm2) - std::sqrt(uu * vv), 0.0);
    norm2 = low * low;
  }
}

// One ACA step on row i: true if it added a significant rank-one term.
bool HMatrix::Aca::step(int64_t i) {
  get_row(i, r);
  row_used[i] = 1;
  const int64_t j = pivot_column(r);
  if (j < 0) return false;
  const double piv = r[j];
  for (double& x : r) x /= piv;
  get_col(j, u);
  const double uu = dot(u.data(), u.data(), m), vv = dot(r.data(), r.data(), n);
  if (norm2 > 0.0 && std::sqrt(uu * vv) <= std::max(h.hp_.eps * std::sqrt(norm2), budget_abs))
    return false;
  col_used[j] = 1;
  update_norm(uu, vv);
  U.push_back(u);
  V.push_back(r);
  last_u = u;
  return true;
}

// Converged?  Checks random unused node rows and node columns against the
// block's error budget; returns the node to restart from, -1 if none failed.
int64_t HMatrix::Aca::check_residuals() {
  const int checks = h.hp_.checks;
  const double budget = std::max(h.hp_.eps * std::sqrt(std::max(norm2, 0.0)), budget_abs);
  int64_t next = -1;
  for (int c = 0; c < checks && next < 0 && rounds < 8 * checks; ++c, ++rounds) {
    const int64_t rn = random_index(tau.size(), [&](int64_t t) { return !node_done[t]; });
    if (rn >= 0)
      for (int k = 0; k < 3 && next < 0; ++k) {
        get_row(3 * rn + k, r);
        if (std::sqrt(dot(r.data(), r.data(), n)) > budget) next = rn;
      }
    if (next >= 0) break;
    const int64_t cn = random_index(sig.size(), [&](int64_t t) {
      return !(col_used[3 * t] && col_used[3 * t + 1] && col_used[3 * t + 2]);
    });
    if (cn >= 0)
      for (int k = 0; k < 6 && next < 0; ++k) {
        const int64_t j = (k < 3 ? 0 : nH) + 3 * cn + k % 3;
        get_col(j, u);
        if (std::sqrt(dot(u.data(), u.data(), m)) > budget) next = largest_open_node(u);
      }
  }
  if (next >= 0) ++b.aca_checks_failed;
  return next;
}

// The iteration over pivot nodes: false if the rank reached maxk (dense).
bool HMatrix::Aca::run() {
  int64_t p = 0;  // pivot node (local index in tau)
  while (true) {
    bool added = false;
    node_done[p] = 1;
    for (int c = 0; c < 3; ++c) {
      if (row_used[3 * p + c]) continue;
      if (static_cast<int64_t>(U.size()) >= maxk) return false;
      added |= step(3 * p + c);
    }
    const int64_t next = added ? largest_open_node(last_u) : check_residuals();
    if (next < 0) return true;
    p = next;
  }
}

// The terms into block b as factors of A (G columns back on their own scale,
// negated where the displacement is given), their H row sums into rs and
// their B W rows into bw.
void HMatrix::Aca::store(double* bw, double* rs) const {
  const int64_t s = h.s_;
  const int k = static_cast<int>(U.size());
  b.aca_rank = k;
  b.rank = k;
  b.U.resize(m * k);
  b.V.resize(nH * k);
  const uint8_t* ku = h.ku_.data() + 3 * sig.begin;
  const double* w = h.w_.data() + 3 * sig.begin * s;
  std::vector<double> t(std::max<int64_t>(s, 1));
  for (int l = 0; l < k; ++l) {
    std::memcpy(&b.U[l * m], U[l].data(), m * sizeof(double));
    const double* vh = V[l].data();
    const double* vg = vh + nH;
    double* va = &b.V[l * nH];
    double hs[3] = {0, 0, 0};
    std::fill(t.begin(), t.end(), 0.0);
    for (int64_t c = 0; c < nH; ++c) {
      const double g = vg[c] / scale;
      hs[c % 3] += vh[c];
      va[c] = ku[c] ? -g : vh[c];
      const double vb = ku[c] ? -vh[c] : g;
      for (int64_t q2 = 0; q2 < s; ++q2) t[q2] += vb * w[c * s + q2];
    }
    // H row sums and B W of this rank-one term
    const double* ul = U[l].data();
    for (int64_t i = 0; i < m; ++i) {
      double* sums = rs + 3 * (3 * tau.begin + i);
      for (int c = 0; c < 3; ++c) sums[c] += ul[i] * hs[c];
      double* y = bw + (3 * tau.begin + i) * s;
      for (int64_t q2 = 0; q2 < s; ++q2) y[q2] += ul[i] * t[q2];
    }
  }
}

namespace {

// Terms that may be rounded (b's factors on the balanced scale, m and n
// rows): the longest tail whose rounding error, about 2 u |u_l| |v_l| per
// term (u the unit roundoff), stays within a quarter of the block's budget
// goes to half precision, the next longest within another quarter to single.
// Sets b.kd and b.kf.
void choose_precisions(HBlock& b, int64_t m, int64_t n, double eps, double budget_abs) {
  std::vector<double> c(b.rank);
  double total = 0.0;
  for (int l = 0; l < b.rank; ++l) {
    const double uu = dot(&b.U[l * m], &b.U[l * m], m);
    const double vv = dot(&b.V[l * n], &b.V[l * n], n);
    c[l] = uu * vv;
    total += c[l];
  }
  const double allowed = 0.25 * std::max(eps * std::sqrt(total), budget_abs);
  auto tail_start = [&](int end, double unit) {
    double tail = 0.0;
    int k = end;
    while (k > 0 && unit * std::sqrt(tail + c[k - 1]) <= allowed) tail += c[--k];
    return k;
  };
  const int kh0 = tail_start(b.rank, std::ldexp(1.0, -10));
  b.kd = tail_start(kh0, std::ldexp(1.0, -23));
  b.kf = kh0 - b.kd;
}

// Moves terms kd .. kd + kf - 1 of b's factors (m and n rows) to single
// precision and the remaining kh() to half precision (HBlock).
void store_mixed(HBlock& b, int64_t m, int64_t n) {
  const int kh0 = b.kd + b.kf;
  b.Uf.assign(b.U.begin() + m * b.kd, b.U.begin() + m * kh0);
  b.Vf.assign(b.V.begin() + n * b.kd, b.V.begin() + n * kh0);
  b.Uh.resize(m * b.kh());
  b.Vh.resize(n * b.kh());
  b.sh.resize(2 * b.kh());
  for (int l = kh0; l < b.rank; ++l) {
    const int t = l - kh0;
    for (int side = 0; side < 2; ++side) {
      const int64_t len = side ? n : m;
      const double* src = (side ? b.V.data() : b.U.data()) + l * len;
      half* dst = (side ? b.Vh.data() : b.Uh.data()) + t * len;
      double mx = 0.0;
      for (int64_t i = 0; i < len; ++i) mx = std::max(mx, std::fabs(src[i]));
      const double sc = mx > 0.0 ? mx : 1.0;
      for (int64_t i = 0; i < len; ++i) dst[i] = to_half(src[i] / sc);
      b.sh[2 * t + side] = sc;
    }
  }
  b.U.resize(m * b.kd);
  b.V.resize(n * b.kd);
  b.U.shrink_to_fit();
  b.V.shrink_to_fit();
}

}  // namespace

void HMatrix::fill_aca(HBlock& b, uint64_t seed, double* bw, double* rs) const {
  Aca aca(*this, b, seed);
  if (!aca.run()) {
    fill_dense(b, bw, rs);
    return;
  }
  aca.store(bw, rs);
  const int64_t m = aca.m, nH = aca.nH;
  const uint8_t* ku = ku_.data() + 3 * aca.sig.begin;
  // recompress with A's G columns on the H scale again (else the SVD
  // truncation, relative to the block norm, would drop them when mu is large)
  for (int l = 0; l < b.rank; ++l)
    for (int64_t c = 0; c < nH; ++c)
      if (ku[c]) b.V[l * nH + c] *= aca.scale;
  recompress(b, m, nH, aca.budget_abs);
  b.kd = b.rank;
  b.kf = 0;
  if (hp_.mixed && b.rank > 0) choose_precisions(b, m, nH, hp_.eps, aca.budget_abs);
  for (int l = 0; l < b.rank; ++l)
    for (int64_t c = 0; c < nH; ++c)
      if (ku[c]) b.V[l * nH + c] /= aca.scale;
  if (b.kd < b.rank) store_mixed(b, m, nH);
}

// Truncation of U V^T to the block's own accuracy (truncate_lowrank, la/lowrank.cpp).
// Called inside the OpenMP build: a LAPACK failure (never seen) keeps the
// block as it is rather than letting an exception leave the parallel region.
void HMatrix::recompress(HBlock& b, int64_t m, int64_t n, double abs_tol) const {
  if (!lapack_.ok() || b.rank <= 0) return;
  std::vector<double> U = b.U, V = b.V;
  int k = b.rank;
  try {
    truncate_lowrank(U, V, m, n, k, hp_.eps, lapack_, abs_tol);
  } catch (const std::exception&) {
    return;
  }
  b.U.swap(U);
  b.V.swap(V);
  b.rank = k;
}

}  // namespace bemcontact
