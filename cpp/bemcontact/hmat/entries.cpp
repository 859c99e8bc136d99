// Rows, columns and single entries of H and G from the element integrals:
// what the H-matrix's blocks are filled from, and the exact entries and G
// columns it answers afterwards (see hmatrix.hpp).
#include <algorithm>
#include <unordered_map>
#include <vector>

#include "hmat/hmatrix.hpp"
#include "parallel.hpp"

namespace bemcontact {

namespace {

int local_index(const Element& e, int64_t node) {
  for (int k = 0; k < e.n; ++k)
    if (e.f[k] == node) return k;
  return -1;
}

}  // namespace

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
  ExceptionGuard guard;
#pragma omp parallel for schedule(dynamic, 16) num_threads(std::max(threads, 1))
  for (int64_t p = 0; p < n_; ++p) guard.run([&] {
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
  });
  guard.rethrow();
}

}  // namespace bemcontact
