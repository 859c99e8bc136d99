#include "hmat/hmatrix.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <numeric>
#include <unordered_map>

#include "la/lowrank.hpp"

#ifdef _OPENMP
#include <omp.h>
#endif

namespace bemcontact {

namespace {

inline uint64_t splitmix(uint64_t& s) {
  uint64_t z = (s += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

double box_diam(const HCluster& c) {
  double s = 0.0;
  for (int d = 0; d < 3; ++d) s += (c.hi[d] - c.lo[d]) * (c.hi[d] - c.lo[d]);
  return std::sqrt(s);
}

double box_dist(const HCluster& a, const HCluster& b) {
  double s = 0.0;
  for (int d = 0; d < 3; ++d) {
    const double g = std::max({0.0, a.lo[d] - b.hi[d], b.lo[d] - a.hi[d]});
    s += g * g;
  }
  return std::sqrt(s);
}

double center_dist(const HCluster& a, const HCluster& b) {
  double s = 0.0;
  for (int d = 0; d < 3; ++d) {
    const double g = 0.5 * (a.lo[d] + a.hi[d] - b.lo[d] - b.hi[d]);
    s += g * g;
  }
  return std::sqrt(s);
}

// (reassociated into SIMD lanes: the ACA's norm updates spend most of their
// time here; the order is fixed by n, so results do not depend on threads)
inline double dot(const double* a, const double* b, int64_t n) {
  double s = 0.0;
#pragma omp simd reduction(+ : s)
  for (int64_t i = 0; i < n; ++i) s += a[i] * b[i];
  return s;
}

int local_index(const Element& e, int64_t node) {
  for (int k = 0; k < e.n; ++k)
    if (e.f[k] == node) return k;
  return -1;
}

}  // namespace

HMatrix::HMatrix(const MeshView& m, const double* points, int64_t n_points,
                 double shear_modulus, double nu, const QuadratureParams& q, const HParams& hp,
                 const uint8_t* known_u, const double* W, int64_t s, const Lapack& lapack,
                 int threads)
    : n_(n_points),
      points_(points),
      K_(shear_modulus, nu),
      q_(q),
      hp_(hp),
      lapack_(lapack),
      mu_(shear_modulus),
      s_(s) {
  const auto t0 = std::chrono::steady_clock::now();
  els_ = prepare_elements(m, std::min(q.max_order, kMaxCachedOrder), threads);
  // functional node -> elements (CSR)
  n2e_ptr_.assign(n_ + 1, 0);
  for (const Element& e : els_)
    for (int k = 0; k < e.n; ++k) ++n2e_ptr_[e.f[k] + 1];
  for (int64_t i = 0; i < n_; ++i) n2e_ptr_[i + 1] += n2e_ptr_[i];
  n2e_.assign(n2e_ptr_[n_], 0);
  {
    std::vector<int64_t> fill(n2e_ptr_.begin(), n2e_ptr_.end() - 1);
    for (int64_t ie = 0; ie < static_cast<int64_t>(els_.size()); ++ie)
      for (int k = 0; k < els_[ie].n; ++k) n2e_[fill[els_[ie].f[k]]++] = ie;
  }
  // support box of every node: its elements' geometric nodes (padded for curvature)
  std::vector<double> sup_lo(3 * n_, INFINITY), sup_hi(3 * n_, -INFINITY);
  for (int64_t i = 0; i < n_; ++i) {
    for (int64_t a = n2e_ptr_[i]; a < n2e_ptr_[i + 1]; ++a) {
      const Element& e = els_[n2e_[a]];
      for (int d = 0; d < 3; ++d) {
        sup_lo[3 * i + d] = std::min(sup_lo[3 * i + d], e.centroid[d] - e.radius);
        sup_hi[3 * i + d] = std::max(sup_hi[3 * i + d], e.centroid[d] + e.radius);
      }
    }
    for (int d = 0; d < 3; ++d) {  // a node with no element (cannot happen): its point
      sup_lo[3 * i + d] = std::min(sup_lo[3 * i + d], points[3 * i + d]);
      sup_hi[3 * i + d] = std::max(sup_hi[3 * i + d], points[3 * i + d]);
    }
  }
  perm_.resize(n_);
  std::iota(perm_.begin(), perm_.end(), 0);
  clusters_.reserve(4 * (n_ / std::max(hp.leaf_size, 1) + 1));
  build_cluster(0, n_, sup_lo, sup_hi, std::max(hp.leaf_size, 1));
  pos_.assign(n_, 0);
  for (int64_t p = 0; p < n_; ++p) pos_[perm_[p]] = p;
  pts_.resize(3 * n_);
  for (int64_t p = 0; p < n_; ++p)
    for (int d = 0; d < 3; ++d) pts_[3 * p + d] = points[3 * perm_[p] + d];
  ku_.resize(3 * n_);
  w_.assign(3 * n_ * s_, 0.0);
  for (int64_t p = 0; p < n_; ++p)
    for (int c = 0; c < 3; ++c) {
      ku_[3 * p + c] = known_u[3 * perm_[p] + c] ? 1 : 0;
      if (s_) std::memcpy(&w_[(3 * p + c) * s_], W + (3 * perm_[p] + c) * s_, s_ * sizeof(double));
    }
  build_blocks(0, 0, hp.eta);
  if (hp.global) estimate_norms(threads);
  // fill, largest blocks first (dynamic schedule balances the rest)
  std::vector<int64_t> order(blocks_.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int64_t a, int64_t b) {
    const auto sa = clusters_[blocks_[a].tau].size() * clusters_[blocks_[a].sigma].size();
    const auto sb = clusters_[blocks_[b].tau].size() * clusters_[blocks_[b].sigma].size();
    return sa > sb;
  });
  const int64_t nb = static_cast<int64_t>(blocks_.size());
  const int nt = std::max(threads, 1);
  // thread-private B W (3N x s) and H row sums (3N x 3), permuted order
  std::vector<std::vector<double>> bw_t(nt), rs_t(nt);
#pragma omp parallel num_threads(nt)
  {
#ifdef _OPENMP
    const int tid = omp_get_thread_num();
#else
    const int tid = 0;
#endif
    bw_t[tid].assign(3 * n_ * s_, 0.0);
    rs_t[tid].assign(9 * n_, 0.0);
#pragma omp for schedule(dynamic, 1)
    for (int64_t t = 0; t < nb; ++t) {
      HBlock& b = blocks_[order[t]];
      const auto tb = std::chrono::steady_clock::now();
      const bool was_dense = b.rank < 0;
      if (was_dense)
        fill_dense(b, bw_t[tid].data(), rs_t[tid].data());
      else
        fill_aca(b, 0x5eedull + static_cast<uint64_t>(order[t]), bw_t[tid].data(),
                 rs_t[tid].data());
      const double dt =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - tb).count();
      if (was_dense) {
#pragma omp atomic
        dense_s_ += dt;
      } else {
#pragma omp atomic
        aca_s_ += dt;
      }
    }
  }
  // sum the threads in a fixed order (results independent of the schedule up
  // to the order of two-term sums)
  std::vector<double>& rs = rs_t[0];
  std::vector<double>& bwp = bw_t[0];
  for (int th = 1; th < nt; ++th) {
    for (size_t i = 0; i < rs.size(); ++i) rs[i] += rs_t[th][i];
    for (size_t i = 0; i < bwp.size(); ++i) bwp[i] += bw_t[th][i];
  }
  // rigid-body translation: H_ii = -sum_{j != i} H_ij per component
  diag_.assign(9 * n_, 0.0);
  for (int64_t p = 0; p < n_; ++p)
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) diag_[9 * p + 3 * r + c] = -rs[3 * (3 * p + r) + c];
  // ... into A (traction-given columns) or B W (displacement-given: B = -H)
  for (HBlock& b : blocks_) {
    if (b.tau != b.sigma) continue;
    const HCluster& tau = clusters_[b.tau];
    const int64_t nc = 3 * tau.size();
    for (int64_t p = tau.begin; p < tau.end; ++p) {
      const int64_t lp = p - tau.begin;
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) {
          const double h = diag_[9 * p + 3 * r + c];
          if (!ku_[3 * p + c]) {
            b.A[(3 * lp + r) * nc + 3 * lp + c] = h;
          } else {
            for (int64_t q2 = 0; q2 < s_; ++q2)
              bwp[(3 * p + r) * s_ + q2] -= h * w_[(3 * p + c) * s_ + q2];
          }
        }
    }
  }
  bw_.assign(3 * n_ * s_, 0.0);
  for (int64_t p = 0; p < n_; ++p)
    for (int c = 0; c < 3; ++c)
      if (s_) std::memcpy(&bw_[(3 * perm_[p] + c) * s_], &bwp[(3 * p + c) * s_], s_ * sizeof(double));
  w_.clear();
  w_.shrink_to_fit();
  points_ = nullptr;
  build_s_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Root-mean-square entries of H (with its rigid-body diagonal) and of G,
// from the full rows of norm_samples nodes spread over the permuted order
// (neighbouring nodes in it are neighbours in space).
void HMatrix::estimate_norms(int threads) {
  const int64_t ns = std::min<int64_t>(n_, std::max(hp_.norm_samples, 1));
  const HCluster& root = clusters_[0];
  std::vector<int64_t> all(els_.size());
  std::iota(all.begin(), all.end(), 0);
  std::vector<double> sh(ns, 0.0), sg(ns, 0.0);
#pragma omp parallel num_threads(std::max(threads, 1))
  {
    std::vector<double> row(3 * 6 * n_);
#pragma omp for schedule(dynamic, 1)
    for (int64_t t = 0; t < ns; ++t) {
      const int64_t p = (2 * t + 1) * n_ / (2 * ns);
      node_rows(p, root, all, row.data());
      const int64_t nc = 3 * n_;
      double h2 = 0.0, g2 = 0.0;
      for (int r = 0; r < 3; ++r) {
        const double* h = &row[r * 6 * n_];
        const double* g = h + nc;
        double diag[3] = {0, 0, 0};
        for (int64_t c = 0; c < nc; ++c) {
          h2 += h[c] * h[c];
          g2 += g[c] * g[c];
          diag[c % 3] -= h[c];
        }
        for (int c = 0; c < 3; ++c) h2 += diag[c] * diag[c];
      }
      sh[t] = h2;
      sg[t] = g2;
    }
  }
  double h2 = 0.0, g2 = 0.0;
  for (int64_t t = 0; t < ns; ++t) {
    h2 += sh[t];
    g2 += sg[t];
  }
  // (3 ns sampled rows) of (3N) entries each
  const double entries = 3.0 * static_cast<double>(ns) * 3.0 * static_cast<double>(n_);
  rms_h_ = std::sqrt(h2 / entries);
  rms_g_ = std::sqrt(g2 / entries);
}

double HMatrix::block_budget(int64_t m, int64_t n, double scale) const {
  if (!hp_.global) return 0.0;
  return hp_.eps * std::sqrt(static_cast<double>(m) * static_cast<double>(n)) *
         std::min(rms_h_, scale * rms_g_);
}

int HMatrix::build_cluster(int64_t begin, int64_t end, const std::vector<double>& sup_lo,
                           const std::vector<double>& sup_hi, int leaf_size) {
  const int id = static_cast<int>(clusters_.size());
  clusters_.emplace_back();
  HCluster c;
  c.begin = begin;
  c.end = end;
  double plo[3] = {INFINITY, INFINITY, INFINITY}, phi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (int d = 0; d < 3; ++d) {
    c.lo[d] = INFINITY;
    c.hi[d] = -INFINITY;
  }
  for (int64_t p = begin; p < end; ++p) {
    const int64_t i = perm_[p];
    for (int d = 0; d < 3; ++d) {
      c.lo[d] = std::min(c.lo[d], sup_lo[3 * i + d]);
      c.hi[d] = std::max(c.hi[d], sup_hi[3 * i + d]);
      plo[d] = std::min(plo[d], points_[3 * i + d]);
      phi[d] = std::max(phi[d], points_[3 * i + d]);
    }
  }
  if (end - begin > leaf_size) {
    int axis = 0;
    for (int d = 1; d < 3; ++d)
      if (phi[d] - plo[d] > phi[axis] - plo[axis]) axis = d;
    const int64_t mid = begin + (end - begin) / 2;
    const double* pts = points_;
    std::nth_element(perm_.begin() + begin, perm_.begin() + mid, perm_.begin() + end,
                     [pts, axis](int64_t a, int64_t b) {
                       const double xa = pts[3 * a + axis], xb = pts[3 * b + axis];
                       return xa < xb || (xa == xb && a < b);
                     });
    const int c0 = build_cluster(begin, mid, sup_lo, sup_hi, leaf_size);
    const int c1 = build_cluster(mid, end, sup_lo, sup_hi, leaf_size);
    c.child[0] = c0;
    c.child[1] = c1;
  }
  clusters_[id] = c;
  return id;
}

void HMatrix::build_blocks(int tau, int sigma, double eta) {
  const HCluster& a = clusters_[tau];
  const HCluster& b = clusters_[sigma];
  const double dist = box_dist(a, b);
  HBlock blk;
  blk.tau = tau;
  blk.sigma = sigma;
  if (dist > 0.0 && std::min(box_diam(a), box_diam(b)) <= eta * dist) {
    blk.rank = 0;
    blocks_.push_back(std::move(blk));
    return;
  }
  if (a.leaf() || b.leaf()) {
    blk.rank = -1;
    blocks_.push_back(std::move(blk));
    return;
  }
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j) build_blocks(a.child[i], b.child[j], eta);
}

std::vector<int64_t> HMatrix::support_elements(const HCluster& c) const {
  std::vector<int64_t> out;
  for (int64_t p = c.begin; p < c.end; ++p) {
    const int64_t i = perm_[p];
    out.insert(out.end(), n2e_.begin() + n2e_ptr_[i], n2e_.begin() + n2e_ptr_[i + 1]);
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

void HMatrix::node_rows(int64_t p, const HCluster& sigma, const std::vector<int64_t>& elems,
                        double* out) const {
  const int64_t s = sigma.size(), ld_out = 6 * s;
  std::fill(out, out + 3 * ld_out, 0.0);
  const double* x = pts_.data() + 3 * p;
  const int64_t i = perm_[p];
  double He[3 * 3 * kMaxNodes], Ge[3 * 3 * kMaxNodes];
#pragma omp atomic
  row_integrals_ += static_cast<int64_t>(elems.size());
  for (int64_t ie : elems) {
    const Element& e = els_[ie];
    const int ld = 3 * e.n;
    std::fill(He, He + 3 * ld, 0.0);
    std::fill(Ge, Ge + 3 * ld, 0.0);
    element_influence(e, x, local_index(e, i), K_, q_, true, true, He, Ge);
    for (int k = 0; k < e.n; ++k) {
      const int64_t pj = pos_[e.f[k]];
      if (pj < sigma.begin || pj >= sigma.end) continue;
      const int64_t col = 3 * (pj - sigma.begin);
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) {
          out[r * ld_out + col + c] += He[r * ld + 3 * k + c];
          out[r * ld_out + 3 * s + col + c] += Ge[r * ld + 3 * k + c];
        }
    }
  }
}

void HMatrix::node_cols(int64_t q, const HCluster& tau, double* out,
                        std::unordered_map<int64_t, std::vector<double>>* cache) const {
  const int64_t mt = tau.size();
  std::fill(out, out + 3 * mt * 6, 0.0);
  const int64_t j = perm_[q];
  double He[3 * 3 * kMaxNodes], Ge[3 * 3 * kMaxNodes];
  for (int64_t a = n2e_ptr_[j]; a < n2e_ptr_[j + 1]; ++a) {
    const int64_t ie = n2e_[a];
    const Element& e = els_[ie];
    const int kj = local_index(e, j);
    const int ld = 3 * e.n;
    // the element's influence on every point of tau (all its nodes' columns):
    // neighbouring pivot nodes share elements
    std::vector<double>* block = nullptr;
    if (cache) {
      auto it = cache->find(ie);
      if (it == cache->end()) {
        std::vector<double>& v = (*cache)[ie];
        v.assign(mt * 6 * ld, 0.0);
#pragma omp atomic
        col_integrals_ += mt;
        for (int64_t p = tau.begin; p < tau.end; ++p) {
          double* h = v.data() + (p - tau.begin) * 6 * ld;
          element_influence(e, pts_.data() + 3 * p, local_index(e, perm_[p]), K_, q_, true, true,
                            h, h + 3 * ld);
        }
        block = &v;
      } else {
        block = &it->second;
      }
    }
    for (int64_t p = tau.begin; p < tau.end; ++p) {
      const double* h;
      const double* g;
      if (block) {
        h = block->data() + (p - tau.begin) * 6 * ld;
        g = h + 3 * ld;
      } else {
        std::fill(He, He + 3 * ld, 0.0);
        std::fill(Ge, Ge + 3 * ld, 0.0);
        element_influence(e, pts_.data() + 3 * p, local_index(e, perm_[p]), K_, q_, true, true,
                          He, Ge);
        h = He;
        g = Ge;
      }
      double* o = out + 3 * (p - tau.begin) * 6;
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) {
          o[r * 6 + c] += h[r * ld + 3 * kj + c];
          o[r * 6 + 3 + c] += g[r * ld + 3 * kj + c];
        }
    }
  }
}

void HMatrix::fill_dense(HBlock& b, double* bw, double* rs) const {
  const HCluster& tau = clusters_[b.tau];
  const HCluster& sig = clusters_[b.sigma];
  const int64_t s = sig.size(), nc = 3 * s, mr = 3 * tau.size();
  const std::vector<int64_t> elems = support_elements(sig);
  b.rank = -1;
  b.A.assign(mr * nc, 0.0);
  b.U.clear();
  b.V.clear();
  std::vector<double> row(3 * 6 * s);
  const uint8_t* ku = ku_.data() + 3 * sig.begin;
  const double* w = w_.data() + 3 * sig.begin * s_;
  for (int64_t p = tau.begin; p < tau.end; ++p) {
    node_rows(p, sig, elems, row.data());
    const int64_t r0 = 3 * (p - tau.begin);
    for (int r = 0; r < 3; ++r) {
      const double* h = &row[r * 6 * s];
      const double* g = h + nc;
      double* a = &b.A[(r0 + r) * nc];
      double* y = bw + (3 * p + r) * s_;
      double* sums = rs + 3 * (3 * p + r);
      for (int64_t c = 0; c < nc; ++c) {
        sums[c % 3] += h[c];
        a[c] = ku[c] ? -g[c] : h[c];
        const double bc = ku[c] ? -h[c] : g[c];
        if (bc != 0.0)
          for (int64_t q2 = 0; q2 < s_; ++q2) y[q2] += bc * w[c * s_ + q2];
      }
    }
  }
}

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
void HMatrix::fill_aca(HBlock& b, uint64_t seed, double* bw, double* rs) const {
  const HCluster& tau = clusters_[b.tau];
  const HCluster& sig = clusters_[b.sigma];
  const int64_t m = 3 * tau.size(), nH = 3 * sig.size(), n = 2 * nH;
  const double scale = 2.0 * mu_ / std::max(center_dist(tau, sig), 1e-300);
  const double budget_abs = block_budget(m, nH, scale);
  const std::vector<int64_t> elems = support_elements(sig);
  // node rows (3 x n) and node columns (m x 6) computed so far: one element
  // integration serves the three components (and H and G) at once
  std::vector<std::vector<double>> row_cache(tau.size()), col_cache(sig.size());
  std::unordered_map<int64_t, std::vector<double>> elem_cache;
  std::vector<std::vector<double>> U, V;
  std::vector<char> row_used(m, 0), col_used(n, 0), node_done(tau.size(), 0);
  uint64_t rng = seed;
  int64_t maxk = std::min(m, n);
  if (hp_.max_rank > 0) maxk = std::min<int64_t>(maxk, hp_.max_rank);
  // dense is cheaper to store beyond this rank
  maxk = std::min(maxk, (m * n) / (m + n) + 1);

  auto get_row = [&](int64_t i, std::vector<double>& r) {
    const int64_t p = i / 3;
    std::vector<double>& cached = row_cache[p];
    if (cached.empty()) {
      cached.resize(3 * n);
      node_rows(tau.begin + p, sig, elems, cached.data());
    }
    const double* src = cached.data() + (i % 3) * n;
    r.assign(src, src + n);
    for (int64_t c = nH; c < n; ++c) r[c] *= scale;
    for (size_t l = 0; l < U.size(); ++l) {
      const double a = U[l][i];
      const double* v = V[l].data();
      for (int64_t c = 0; c < n; ++c) r[c] -= a * v[c];
    }
  };
  auto get_col = [&](int64_t j, std::vector<double>& u) {
    const int64_t jj = j % nH;
    const int64_t qn = jj / 3;
    std::vector<double>& colbuf = col_cache[qn];
    if (colbuf.empty()) {
      colbuf.resize(m * 6);
      node_cols(sig.begin + qn, tau, colbuf.data(), &elem_cache);
    }
    const bool g = j >= nH;
    const int comp = static_cast<int>(jj % 3) + (g ? 3 : 0);
    const double f = g ? scale : 1.0;
    u.resize(m);
    for (int64_t t = 0; t < m; ++t) u[t] = colbuf[t * 6 + comp] * f;
    for (size_t l = 0; l < U.size(); ++l) {
      const double a = V[l][j];
      const double* w = U[l].data();
      for (int64_t t = 0; t < m; ++t) u[t] -= a * w[t];
    }
  };
  auto random_index = [&](int64_t len, auto&& usable) -> int64_t {
    int64_t cnt = 0;
    for (int64_t t = 0; t < len; ++t) cnt += usable(t);
    if (!cnt) return -1;
    int64_t k = static_cast<int64_t>(splitmix(rng) % static_cast<uint64_t>(cnt));
    for (int64_t t = 0; t < len; ++t)
      if (usable(t) && k-- == 0) return t;
    return -1;
  };

  double norm2 = 0.0;
  std::vector<double> r, u, last_u;
  bool dense = false;
  // one ACA step on row i: true if it added a significant rank-one term
  auto step = [&](int64_t i) -> bool {
    get_row(i, r);
    row_used[i] = 1;
    int64_t j = -1;
    double best = 0.0;
    for (int64_t c = 0; c < n; ++c)
      if (!col_used[c] && std::fabs(r[c]) > best) {
        best = std::fabs(r[c]);
        j = c;
      }
    if (j < 0 || best <= 1e-300) return false;
    const double piv = r[j];
    for (double& x : r) x /= piv;
    get_col(j, u);
    const double uu = dot(u.data(), u.data(), m), vv = dot(r.data(), r.data(), n);
    if (norm2 > 0.0 && std::sqrt(uu * vv) <= std::max(hp_.eps * std::sqrt(norm2), budget_abs))
      return false;
    col_used[j] = 1;
    // norm2 is a lower bound of |S_k|_F^2 (exact while the terms are large):
    // the exact update costs a pass over all previous terms (the k^2 (m + n)
    // part of the ACA); once a term is below 1e-3 |S| the triangle
    // inequality |S_k| >= |S_{k-1}| - |u||v| keeps a lower bound instead,
    // which only makes the stopping test above stricter
    if (uu * vv > 1e-6 * norm2) {
      for (size_t l = 0; l < U.size(); ++l)
        norm2 += 2.0 * dot(U[l].data(), u.data(), m) * dot(V[l].data(), r.data(), n);
      norm2 += uu * vv;
    } else {
      const double low = std::max(std::sqrt(norm2) - std::sqrt(uu * vv), 0.0);
      norm2 = low * low;
    }
    U.push_back(u);
    V.push_back(r);
    last_u = u;
    return true;
  };

  int64_t p = 0;  // pivot node (local index in tau)
  int rounds = 0;
  while (true) {
    bool added = false;
    node_done[p] = 1;
    for (int c = 0; c < 3; ++c) {
      if (row_used[3 * p + c]) continue;
      if (static_cast<int64_t>(U.size()) >= maxk) {
        dense = true;
        break;
      }
      added |= step(3 * p + c);
    }
    if (dense) break;
    int64_t next = -1;
    if (added) {
      double bu = -1.0;
      for (int64_t t = 0; t < m; ++t)
        if (!node_done[t / 3] && std::fabs(last_u[t]) > bu) {
          bu = std::fabs(last_u[t]);
          next = t / 3;
        }
    } else {
      // converged?  check random unused node rows and node columns
      const double budget = std::max(hp_.eps * std::sqrt(std::max(norm2, 0.0)), budget_abs);
      for (int c = 0; c < hp_.checks && next < 0 && rounds < 8 * hp_.checks; ++c, ++rounds) {
        const int64_t rn =
            random_index(tau.size(), [&](int64_t t) { return !node_done[t]; });
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
            if (std::sqrt(dot(u.data(), u.data(), m)) > budget) {
              double bu = -1.0;
              for (int64_t t = 0; t < m; ++t)
                if (!node_done[t / 3] && std::fabs(u[t]) > bu) {
                  bu = std::fabs(u[t]);
                  next = t / 3;
                }
            }
          }
      }
      if (next >= 0) ++b.aca_checks_failed;
    }
    if (next < 0) break;
    p = next;
  }
  if (dense) {
    fill_dense(b, bw, rs);
    return;
  }
  const int k = static_cast<int>(U.size());
  b.aca_rank = k;
  b.rank = k;
  b.U.resize(m * k);
  b.V.resize(nH * k);
  const uint8_t* ku = ku_.data() + 3 * sig.begin;
  const double* w = w_.data() + 3 * sig.begin * s_;
  std::vector<double> t(std::max<int64_t>(s_, 1));
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
      for (int64_t q2 = 0; q2 < s_; ++q2) t[q2] += vb * w[c * s_ + q2];
    }
    // H row sums and B W of this rank-one term
    const double* ul = U[l].data();
    for (int64_t r = 0; r < m; ++r) {
      double* sums = rs + 3 * (3 * tau.begin + r);
      for (int c = 0; c < 3; ++c) sums[c] += ul[r] * hs[c];
      double* y = bw + (3 * tau.begin + r) * s_;
      for (int64_t q2 = 0; q2 < s_; ++q2) y[q2] += ul[r] * t[q2];
    }
  }
  // recompress with A's G columns on the H scale again (else the SVD
  // truncation, relative to the block norm, would drop them when mu is large)
  for (int l = 0; l < k; ++l)
    for (int64_t c = 0; c < nH; ++c)
      if (ku[c]) b.V[l * nH + c] *= scale;
  recompress(b, m, nH, budget_abs);
  // terms that may be rounded: the longest tail whose rounding error, about
  // 2 u |u_l| |v_l| per term (u the unit roundoff; on the balanced scale),
  // stays within a quarter of the block's budget goes to half precision, the
  // next longest within another quarter to single
  b.kd = b.rank;
  b.kf = 0;
  if (hp_.mixed && b.rank > 0) {
    std::vector<double> c(b.rank);
    double total = 0.0;
    for (int l = 0; l < b.rank; ++l) {
      const double uu = dot(&b.U[l * m], &b.U[l * m], m);
      const double vv = dot(&b.V[l * nH], &b.V[l * nH], nH);
      c[l] = uu * vv;
      total += c[l];
    }
    const double allowed = 0.25 * std::max(hp_.eps * std::sqrt(total), budget_abs);
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
  for (int l = 0; l < b.rank; ++l)
    for (int64_t c = 0; c < nH; ++c)
      if (ku[c]) b.V[l * nH + c] /= scale;
  if (b.kd < b.rank) {
    const int kh0 = b.kd + b.kf;
    b.Uf.assign(b.U.begin() + m * b.kd, b.U.begin() + m * kh0);
    b.Vf.assign(b.V.begin() + nH * b.kd, b.V.begin() + nH * kh0);
    b.Uh.resize(m * b.kh());
    b.Vh.resize(nH * b.kh());
    b.sh.resize(2 * b.kh());
    for (int l = kh0; l < b.rank; ++l) {
      const int t = l - kh0;
      for (int side = 0; side < 2; ++side) {
        const int64_t len = side ? nH : m;
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
    b.V.resize(nH * b.kd);
    b.U.shrink_to_fit();
    b.V.shrink_to_fit();
  }
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

// y (mr x k) += U (V^T x): U mr x rk, V nc x rk (columns contiguous), double or float.
// scales: per term (u-scale, v-scale) multiplying U's and V's column (half
// precision), or null
template <class T>
void lowrank_apply(const T* U, const T* V, int rk, int64_t mr, int64_t nc, const double* xs,
                   double* yo, int64_t k, std::vector<double>& t,
                   const double* scales = nullptr) {
  if (rk <= 0) return;
  t.assign(rk * k, 0.0);
  for (int l = 0; l < rk; ++l) {
    const T* v = V + l * nc;
    double* tl = t.data() + l * k;
    if (k == 1) {  // (SIMD lanes: a strict-order sum is latency bound)
      double s = 0.0;
#pragma omp simd reduction(+ : s)
      for (int64_t c = 0; c < nc; ++c) s += static_cast<double>(v[c]) * xs[c];
      tl[0] = s;
      continue;
    }
    for (int64_t c = 0; c < nc; ++c) {
      const double* xc = xs + c * k;
      const double vc = v[c];
      for (int64_t q = 0; q < k; ++q) tl[q] += vc * xc[q];
    }
  }
  if (scales)
    for (int l = 0; l < rk; ++l)
      for (int64_t q = 0; q < k; ++q) t[l * k + q] *= scales[2 * l] * scales[2 * l + 1];
  for (int l = 0; l < rk; ++l) {
    const T* ul = U + l * mr;
    const double* tl = t.data() + l * k;
    if (k == 1) {
      const double f = tl[0];
      for (int64_t r = 0; r < mr; ++r) yo[r] += static_cast<double>(ul[r]) * f;
      continue;
    }
    for (int64_t r = 0; r < mr; ++r) {
      double* yr = yo + r * k;
      const double f = ul[r];
      for (int64_t q = 0; q < k; ++q) yr[q] += f * tl[q];
    }
  }
}

void HMatrix::apply(const double* x, double* y, int64_t k, int threads) const {
  const int64_t n3 = 3 * n_;
  std::vector<double> xp(n3 * k);
  for (int64_t p = 0; p < n_; ++p)
    for (int c = 0; c < 3; ++c)
      std::memcpy(&xp[(3 * p + c) * k], x + (3 * perm_[p] + c) * k, k * sizeof(double));
  const int nt = std::max(threads, 1);
  std::vector<std::vector<double>> acc(nt);
  const int64_t nb = static_cast<int64_t>(blocks_.size());
#pragma omp parallel num_threads(nt)
  {
#ifdef _OPENMP
    const int tid = omp_get_thread_num();
#else
    const int tid = 0;
#endif
    std::vector<double>& yt = acc[tid];
    yt.assign(n3 * k, 0.0);
    std::vector<double> t;
    std::vector<float> uf, vf;
#pragma omp for schedule(dynamic, 4)
    for (int64_t bi = 0; bi < nb; ++bi) {
      const HBlock& B = blocks_[bi];
      const HCluster& tau = clusters_[B.tau];
      const HCluster& sig = clusters_[B.sigma];
      const int64_t mr = 3 * tau.size(), nc = 3 * sig.size();
      const double* xs = xp.data() + 3 * sig.begin * k;
      double* yo = yt.data() + 3 * tau.begin * k;
      if (B.rank < 0 && k == 1) {
        for (int64_t r = 0; r < mr; ++r) yo[r] += dot(B.A.data() + r * nc, xs, nc);
      } else if (B.rank < 0) {
        for (int64_t r = 0; r < mr; ++r) {
          const double* a = B.A.data() + r * nc;
          double* yr = yo + r * k;
          for (int64_t c = 0; c < nc; ++c) {
            const double ac = a[c];
            const double* xc = xs + c * k;
            for (int64_t q = 0; q < k; ++q) yr[q] += ac * xc[q];
          }
        }
      } else if (B.rank > 0) {
        lowrank_apply(B.U.data(), B.V.data(), B.kd, mr, nc, xs, yo, k, t);
        lowrank_apply(B.Uf.data(), B.Vf.data(), B.kf, mr, nc, xs, yo, k, t);
        if (B.kh() > 0) {
          // half -> float in bulk (vectorized conversions), then the float path
          uf.resize(B.Uh.size());
          vf.resize(B.Vh.size());
          for (size_t i = 0; i < uf.size(); ++i) uf[i] = static_cast<float>(B.Uh[i]);
          for (size_t i = 0; i < vf.size(); ++i) vf[i] = static_cast<float>(B.Vh[i]);
          lowrank_apply(uf.data(), vf.data(), B.kh(), mr, nc, xs, yo, k, t, B.sh.data());
        }
      }
    }
  }
  for (int th = 1; th < nt; ++th)
    if (!acc[th].empty())
      for (int64_t t2 = 0; t2 < n3 * k; ++t2) acc[0][t2] += acc[th][t2];
  for (int64_t p = 0; p < n_; ++p)
    for (int c = 0; c < 3; ++c)
      std::memcpy(y + (3 * perm_[p] + c) * k, &acc[0][(3 * p + c) * k], k * sizeof(double));
}

void HMatrix::entries(const int64_t* rows, int64_t nr, const int64_t* cols, int64_t nc,
                      double* out_h, double* out_g) const {
  // every element touching a requested column node
  std::vector<int64_t> elems;
  for (int64_t b = 0; b < nc; ++b) {
    const int64_t j = cols[b] / 3;
    elems.insert(elems.end(), n2e_.begin() + n2e_ptr_[j], n2e_.begin() + n2e_ptr_[j + 1]);
  }
  std::sort(elems.begin(), elems.end());
  elems.erase(std::unique(elems.begin(), elems.end()), elems.end());
  const HCluster& root = clusters_[0];
  const int64_t s = root.size();
  std::vector<double> row(3 * 6 * s);
  int64_t last = -1;
  for (int64_t a = 0; a < nr; ++a) {
    const int64_t i = rows[a] / 3, ri = rows[a] % 3;
    if (i != last) {
      node_rows(pos_[i], root, elems, row.data());
      last = i;
    }
    for (int64_t b = 0; b < nc; ++b) {
      const int64_t j = cols[b] / 3, cj = cols[b] % 3;
      const int64_t col = 3 * pos_[j] + cj;
      double h = row[ri * 6 * s + col];
      if (i == j) h = diag_[9 * pos_[i] + 3 * ri + cj];
      out_h[a * nc + b] = h;
      out_g[a * nc + b] = row[ri * 6 * s + 3 * s + col];
    }
  }
}

void HMatrix::g_columns(const int64_t* cols, int64_t nc, double* out, int threads) const {
  std::vector<int64_t> where(3 * n_, -1);  // original dof -> output column
  std::vector<int64_t> elems;
  for (int64_t b = 0; b < nc; ++b) {
    where[cols[b]] = b;
    const int64_t j = cols[b] / 3;
    elems.insert(elems.end(), n2e_.begin() + n2e_ptr_[j], n2e_.begin() + n2e_ptr_[j + 1]);
  }
  std::sort(elems.begin(), elems.end());
  elems.erase(std::unique(elems.begin(), elems.end()), elems.end());
  std::fill(out, out + 3 * n_ * nc, 0.0);
#pragma omp parallel for schedule(dynamic, 16) num_threads(std::max(threads, 1))
  for (int64_t p = 0; p < n_; ++p) {
    const double* x = pts_.data() + 3 * p;
    const int64_t i = perm_[p];
    double He[3 * 3 * kMaxNodes], Ge[3 * 3 * kMaxNodes];
    for (int64_t ie : elems) {
      const Element& e = els_[ie];
      const int ld = 3 * e.n;
      std::fill(Ge, Ge + 3 * ld, 0.0);
      element_influence(e, x, local_index(e, i), K_, q_, false, true, He, Ge);
      for (int k = 0; k < e.n; ++k)
        for (int c = 0; c < 3; ++c) {
          const int64_t col = where[3 * e.f[k] + c];
          if (col < 0) continue;
          for (int r = 0; r < 3; ++r) out[(3 * i + r) * nc + col] += Ge[r * ld + 3 * k + c];
        }
    }
  }
}

int64_t HMatrix::stored_bytes() const {
  int64_t s = 0;
  for (const HBlock& b : blocks_) s += b.stored_bytes();
  return s;
}

}  // namespace bemcontact
