// H-matrix products (see hmatrix.hpp).
#include <cstring>
#include <vector>

#include "hmat/hmatrix.hpp"
#include "parallel.hpp"
#include "la/dot.hpp"

namespace bemcontact {

namespace {

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

}  // namespace

void HMatrix::apply(const double* x, double* y, int64_t k, int threads) const {
  const int64_t n3 = 3 * n_;
  std::vector<double> xp(n3 * k);
  for (int64_t p = 0; p < n_; ++p)
    for (int c = 0; c < 3; ++c)
      std::memcpy(&xp[(3 * p + c) * k], x + (3 * perm_[p] + c) * k, k * sizeof(double));
  const int nt = std::max(threads, 1);
  std::vector<std::vector<double>> acc(nt);
  const int64_t nb = static_cast<int64_t>(blocks_.size());
  ExceptionGuard guard;
#pragma omp parallel num_threads(nt)
  {
    const int tid = thread_num();
    std::vector<double>& yt = acc[tid];
    guard.run([&] { yt.assign(n3 * k, 0.0); });
    std::vector<double> t;
    std::vector<float> uf, vf;
#pragma omp for schedule(dynamic, 4)
    for (int64_t bi = 0; bi < nb; ++bi) guard.run([&] {
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
    });
  }
  guard.rethrow();
  for (int th = 1; th < nt; ++th)
    if (!acc[th].empty())
      for (int64_t t2 = 0; t2 < n3 * k; ++t2) acc[0][t2] += acc[th][t2];
  for (int64_t p = 0; p < n_; ++p)
    for (int c = 0; c < 3; ++c)
      std::memcpy(y + (3 * perm_[p] + c) * k, &acc[0][(3 * p + c) * k], k * sizeof(double));
}

}  // namespace bemcontact
