// The Kelvin fundamental solution of isotropic elasticity (displacement
// kernel U for G, traction kernel T for H) in the form the vectorized element
// integration (bem/integration.cpp) accumulates: per quadrature point the
// kernels are reduced to kTerms scalars (Kelvin U: 1 isotropic + 6 symmetric
// dyadic terms; T: 1 isotropic + 6 symmetric + 3 antisymmetric), which are
// integrated against the basis values and then expanded into the 3 x 3n
// blocks of an element.  Points are taken in chunks of kChunk.
#pragma once

#include <cmath>
#include <cstddef>

namespace bemcontact {

struct Kelvin {
  double c1, c2, a, b;  // U = c1 [a delta + r_i r_j] / r ; T uses b = 1 - 2 nu
  Kelvin(double shear_modulus, double nu)
      : c1(1.0 / (16.0 * M_PI * shear_modulus * (1.0 - nu))),
        c2(1.0 / (8.0 * M_PI * (1.0 - nu))),
        a(3.0 - 4.0 * nu),
        b(1.0 - 2.0 * nu) {}
};

constexpr int kTerms = 17;
constexpr size_t kChunk = 64;

// The 6 symmetric dyadic terms s d_i d_j, (i, j) = 00, 11, 22, 01, 02, 12, of
// point p: q[t * kChunk + p], t = 0..5 (inlined into point_terms's SIMD loop).
inline void dyadic_terms(double* q, size_t p, double s, double d0, double d1, double d2) {
  q[0 * kChunk + p] = s * d0 * d0;
  q[1 * kChunk + p] = s * d1 * d1;
  q[2 * kChunk + p] = s * d2 * d2;
  q[3 * kChunk + p] = s * d0 * d1;
  q[4 * kChunk + p] = s * d0 * d2;
  q[5 * kChunk + p] = s * d1 * d2;
}

// q[m * kChunk + i] (m < kTerms) for the points p0 .. p0 + cnt - 1 of the
// point set c (np points, structure of arrays with stride np: x, y, z, nx, ny,
// nz, w*J, then the basis values; bem/integration.cpp), seen from x
inline void point_terms(const double* c, size_t np, size_t p0, size_t cnt, const double* x,
                        const Kelvin& K, bool want_h, bool want_g, double* q) {
  const double* px = c + p0;
  const double* py = c + np + p0;
  const double* pz = c + 2 * np + p0;
  const double* nx = c + 3 * np + p0;
  const double* ny = c + 4 * np + p0;
  const double* nz = c + 5 * np + p0;
  const double* wj = c + 6 * np + p0;
  const double x0 = x[0], x1 = x[1], x2 = x[2];
  const double c1 = want_g ? K.c1 : 0.0, c2 = want_h ? K.c2 : 0.0, kb = K.b;
#pragma omp simd
  for (size_t p = 0; p < cnt; ++p) {
    const double r0 = px[p] - x0, r1 = py[p] - x1, r2 = pz[p] - x2;
    const double ir = 1.0 / std::sqrt(r0 * r0 + r1 * r1 + r2 * r2);
    const double d0 = r0 * ir, d1 = r1 * ir, d2 = r2 * ir;
    // G: U_ij = sg (a delta_ij + d_i d_j)
    const double sg = c1 * ir * wj[p];
    q[0 * kChunk + p] = sg;
    dyadic_terms(q + 1 * kChunk, p, sg, d0, d1, d2);
    // H: T_ij = sh (drdn (b delta_ij + 3 d_i d_j) - b (d_i n_j - d_j n_i))
    const double sh = -c2 * ir * ir * wj[p];
    const double drdn = d0 * nx[p] + d1 * ny[p] + d2 * nz[p];
    const double s3 = 3.0 * sh * drdn;
    const double sb = sh * kb;
    q[7 * kChunk + p] = sb * drdn;
    dyadic_terms(q + 8 * kChunk, p, s3, d0, d1, d2);
    q[14 * kChunk + p] = -sb * (d0 * ny[p] - d1 * nx[p]);  // antisymmetric (0,1)
    q[15 * kChunk + p] = -sb * (d0 * nz[p] - d2 * nx[p]);  // (0,2)
    q[16 * kChunk + p] = -sb * (d1 * nz[p] - d2 * ny[p]);  // (1,2)
  }
}

// He/Ge += the blocks of acc; the H column of functional node `skip` (the
// collocation point's own node, singular rule) is left alone.
inline void expand_terms(const double* acc, int n, int skip, const Kelvin& K, bool want_h,
                         bool want_g, double* He, double* Ge) {
  const int ld = 3 * n;
  // symmetric index pairs (i, j) -> term offset 0..5
  static const int sym[3][3] = {{0, 3, 4}, {3, 1, 5}, {4, 5, 2}};
  for (int k = 0; k < n; ++k) {
    const double* a = acc;
    if (want_g) {
      const double iso = K.a * a[0 * n + k];
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
          Ge[i * ld + 3 * k + j] += (i == j ? iso : 0.0) + a[(1 + sym[i][j]) * n + k];
    }
    if (want_h && k != skip) {
      const double iso = a[7 * n + k];
      const double an[3] = {a[14 * n + k], a[15 * n + k], a[16 * n + k]};
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
          double v = (i == j ? iso : 0.0) + a[(8 + sym[i][j]) * n + k];
          if (i < j) v += an[i + j - 1];
          else if (i > j) v -= an[i + j - 1];
          He[i * ld + 3 * k + j] += v;
        }
    }
  }
}

}  // namespace bemcontact
