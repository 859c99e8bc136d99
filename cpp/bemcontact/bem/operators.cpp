// Assembly of H, G and the mixed system (see operators.hpp).
#include "bem/operators.hpp"
#include "parallel.hpp"

#include <algorithm>
#include <vector>

namespace bemcontact {

// The three rows of H and G (each 3 x ncol, row-major) of collocation point
// i at x, over all elements, with the diagonal block of H (free term +
// principal value) from rigid-body translation.
static void influence_rows(const std::vector<Element>& els, int64_t i, const double* x,
                           const Kelvin& K, const QuadratureParams& q, int64_t ncol,
                           double* Hrow, double* Grow) {
  double He[3 * 3 * kMaxNodes], Ge[3 * 3 * kMaxNodes];
  std::fill(Hrow, Hrow + 3 * ncol, 0.0);
  std::fill(Grow, Grow + 3 * ncol, 0.0);
  for (const Element& e : els) {
    int local = -1;
    for (int k = 0; k < e.n; ++k)
      if (e.f[k] == i) local = k;
    const int ld = 3 * e.n;
    std::fill(He, He + 3 * ld, 0.0);
    std::fill(Ge, Ge + 3 * ld, 0.0);
    element_influence(e, x, local, K, q, true, true, He, Ge);
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < e.n; ++k) {
        const int64_t col = 3 * e.f[k];
        for (int j = 0; j < 3; ++j) {
          Hrow[r * ncol + col + j] += He[r * ld + 3 * k + j];
          Grow[r * ncol + col + j] += Ge[r * ld + 3 * k + j];
        }
      }
  }
  for (int r = 0; r < 3; ++r)
    for (int j = 0; j < 3; ++j) {
      double acc = 0.0;
      for (int64_t c = j; c < ncol; c += 3) acc += Hrow[r * ncol + c];
      Hrow[r * ncol + 3 * i + j] = -acc;
    }
}

void assemble_influence(const MeshView& m, const double* points, int64_t n_points,
                        double shear_modulus, double nu, const QuadratureParams& q,
                        int threads, double* H, double* G) {
  const std::vector<Element> els = prepare_elements(m, std::min(q.max_order, kMaxCachedOrder), threads);
  const Kelvin K(shear_modulus, nu);
  const int64_t ncol = 3 * n_points;
  ExceptionGuard guard;
#pragma omp parallel for schedule(dynamic, 4) num_threads(threads)
  for (int64_t i = 0; i < n_points; ++i) guard.run([&] {
    influence_rows(els, i, points + 3 * i, K, q, ncol, H + 3 * i * ncol, G + 3 * i * ncol);
  });
  guard.rethrow();
}

void assemble_system(const MeshView& m, const double* points, int64_t n_points,
                     double shear_modulus, double nu, const QuadratureParams& q,
                     const uint8_t* known_u, const double* W, int64_t s, const int64_t* bcols,
                     int64_t nb, int threads, double* A, int64_t lda, double* BW, double* BC) {
  const std::vector<Element> els = prepare_elements(m, std::min(q.max_order, kMaxCachedOrder), threads);
  const Kelvin K(shear_modulus, nu);
  const int64_t ncol = 3 * n_points;
  // Rows in chunks of kRowChunk points, so that the column-major A is written
  // in runs of 3 kRowChunk consecutive entries per column (not one entry per
  // cache line).
  constexpr int64_t kRowChunk = 16;
  const int64_t nchunks = (n_points + kRowChunk - 1) / kRowChunk;
  ExceptionGuard guard;
#pragma omp parallel num_threads(threads)
  {
    std::vector<double> Hrow, Grow;
    guard.run([&] {
      Hrow.resize(3 * kRowChunk * ncol);
      Grow.resize(3 * kRowChunk * ncol);
    });
#pragma omp for schedule(dynamic, 1)
    for (int64_t ch = 0; ch < nchunks; ++ch) guard.run([&] {
      const int64_t i0 = ch * kRowChunk, i1 = std::min(n_points, i0 + kRowChunk);
      const int64_t nr = 3 * (i1 - i0), row0 = 3 * i0;
      for (int64_t i = i0; i < i1; ++i)
        influence_rows(els, i, points + 3 * i, K, q, ncol, Hrow.data() + 3 * (i - i0) * ncol,
                       Grow.data() + 3 * (i - i0) * ncol);
      // A column-major (leading dimension lda): A[row, c]
      for (int64_t c = 0; c < ncol; ++c) {
        double* out = A + lda * c + row0;
        const double* src = known_u[c] ? Grow.data() : Hrow.data();
        const double sign = known_u[c] ? -1.0 : 1.0;
        for (int64_t r = 0; r < nr; ++r) out[r] = sign * src[r * ncol + c];
      }
      for (int64_t r = 0; r < nr; ++r) {
        const double* h = Hrow.data() + r * ncol;
        const double* g = Grow.data() + r * ncol;
        const int64_t row = row0 + r;
        // B = G on traction-given columns, -H on displacement-given ones
        if (s > 0) {
          double* y = BW + row * s;
          std::fill(y, y + s, 0.0);
          for (int64_t c = 0; c < ncol; ++c) {
            const double b = known_u[c] ? -h[c] : g[c];
            if (b == 0.0) continue;
            const double* w = W + c * s;
            for (int64_t t = 0; t < s; ++t) y[t] += b * w[t];
          }
        }
        for (int64_t t = 0; t < nb; ++t) {
          const int64_t c = bcols[t];
          BC[row * nb + t] = known_u[c] ? -h[c] : g[c];
        }
      }
    });
  }
  guard.rethrow();
}

}  // namespace bemcontact
