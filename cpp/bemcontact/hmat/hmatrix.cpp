// H-matrix build (see hmatrix.hpp): element supports, cluster tree, block
// partition, the parallel fill of the blocks (dense here, low rank in
// aca.cpp) and the rigid-body diagonal of H.
#include "hmat/hmatrix.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <numeric>

#include "parallel.hpp"

namespace bemcontact {

HMatrix::HMatrix(const MeshView& m, const double* points, int64_t n_points,
                 double shear_modulus, double nu, const QuadratureParams& q, const HParams& hp,
                 const uint8_t* known_u, const double* W, int64_t s, const Lapack& lapack,
                 int threads)
    : n_(n_points),
      K_(shear_modulus, nu),
      q_(q),
      hp_(hp),
      lapack_(lapack),
      mu_(shear_modulus),
      s_(s) {
  const auto t0 = std::chrono::steady_clock::now();
  els_ = prepare_elements(m, std::min(q.max_order, kMaxCachedOrder), threads);
  index_node_elements();
  std::vector<double> sup_lo, sup_hi;
  support_boxes(points, sup_lo, sup_hi);
  build_cluster_tree(points, n_, sup_lo, sup_hi, std::max(hp.leaf_size, 1), clusters_, perm_);
  permute_inputs(points, known_u, W);
  build_blocks(0, 0, hp.eta);
  if (hp.global) estimate_norms(threads);
  std::vector<double> bwp, rs;
  fill_blocks(threads, bwp, rs);
  add_rigid_diagonal(rs, bwp);
  bw_.assign(3 * n_ * s_, 0.0);
  for (int64_t p = 0; p < n_; ++p)
    for (int c = 0; c < 3; ++c)
      if (s_) std::memcpy(&bw_[(3 * perm_[p] + c) * s_], &bwp[(3 * p + c) * s_], s_ * sizeof(double));
  w_.clear();
  w_.shrink_to_fit();
  build_s_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void HMatrix::index_node_elements() {
  n2e_ptr_.assign(n_ + 1, 0);
  for (const Element& e : els_)
    for (int k = 0; k < e.n; ++k) ++n2e_ptr_[e.f[k] + 1];
  for (int64_t i = 0; i < n_; ++i) n2e_ptr_[i + 1] += n2e_ptr_[i];
  n2e_.assign(n2e_ptr_[n_], 0);
  std::vector<int64_t> fill(n2e_ptr_.begin(), n2e_ptr_.end() - 1);
  for (int64_t ie = 0; ie < static_cast<int64_t>(els_.size()); ++ie)
    for (int k = 0; k < els_[ie].n; ++k) n2e_[fill[els_[ie].f[k]]++] = ie;
}

void HMatrix::support_boxes(const double* points, std::vector<double>& sup_lo,
                            std::vector<double>& sup_hi) const {
  // support box of every node: its elements' geometric nodes (padded for curvature)
  sup_lo.assign(3 * n_, INFINITY);
  sup_hi.assign(3 * n_, -INFINITY);
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
}

void HMatrix::permute_inputs(const double* points, const uint8_t* known_u, const double* W) {
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
}

void HMatrix::fill_blocks(int threads, std::vector<double>& bw, std::vector<double>& rs) {
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
  ExceptionGuard guard;
#pragma omp parallel num_threads(nt)
  {
    const int tid = thread_num();
    guard.run([&] {
      bw_t[tid].assign(3 * n_ * s_, 0.0);
      rs_t[tid].assign(9 * n_, 0.0);
    });
#pragma omp for schedule(dynamic, 1)
    for (int64_t t = 0; t < nb; ++t) guard.run([&] {
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
    });
  }
  guard.rethrow();
  // sum the threads in a fixed order (results independent of the schedule up
  // to the order of two-term sums)
  for (int th = 1; th < nt; ++th) {
    // OpenMP may give fewer threads than asked (thread limits, nesting): the
    // accumulators of threads that never ran are empty
    if (rs_t[th].empty()) continue;
    for (size_t i = 0; i < rs_t[0].size(); ++i) rs_t[0][i] += rs_t[th][i];
    for (size_t i = 0; i < bw_t[0].size(); ++i) bw_t[0][i] += bw_t[th][i];
  }
  rs.swap(rs_t[0]);
  bw.swap(bw_t[0]);
}

void HMatrix::add_rigid_diagonal(const std::vector<double>& rs, std::vector<double>& bw) {
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
              bw[(3 * p + r) * s_ + q2] -= h * w_[(3 * p + c) * s_ + q2];
          }
        }
    }
  }
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
  ExceptionGuard guard;
#pragma omp parallel num_threads(std::max(threads, 1))
  {
    std::vector<double> row;
    guard.run([&] { row.resize(3 * 6 * n_); });
#pragma omp for schedule(dynamic, 1)
    for (int64_t t = 0; t < ns; ++t) guard.run([&] {
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
    });
  }
  guard.rethrow();
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

int64_t HMatrix::stored_bytes() const {
  int64_t s = 0;
  for (const HBlock& b : blocks_) s += b.stored_bytes();
  return s;
}

}  // namespace bemcontact
