// Surface element geometry and nodal bases.
//
// Element types (codes shared with bemcontact.mesh.ElementType):
//   0 tri3, 1 tri6, 2 quad4, 3 quad8 (serendipity), 4 quad9 (Lagrange).
// Node order is gmsh/VTK order. Reference domains: triangle {xi, eta >= 0,
// xi + eta <= 1}; quadrilateral [-1, 1]^2.
//
// Every basis (geometric and functional) is the Lagrange basis of the
// element's polynomial space on a set of local points, obtained by inverting
// a small Vandermonde matrix.  Geometry uses the reference node positions;
// the functional (collocation) basis of an element uses its functional node
// positions, which may be shifted inward for discontinuous nodes.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>

namespace bemcontact {

constexpr int kMaxNodes = 9;

enum ElementType : int { TRI3 = 0, TRI6 = 1, QUAD4 = 2, QUAD8 = 3, QUAD9 = 4 };

inline int nodes_per_element(int t) {
  static const int n[5] = {3, 6, 4, 8, 9};
  return n[t];
}
inline bool is_triangle(int t) { return t == TRI3 || t == TRI6; }
inline int n_corners(int t) { return is_triangle(t) ? 3 : 4; }

// The entry of a per-type table (tri3, tri6, quad4, quad8, quad9) for type t.
template <class T>
inline T by_type(int t, T tri3, T tri6, T quad4, T quad8, T quad9) {
  switch (t) {
    case TRI3: return tri3;
    case TRI6: return tri6;
    case QUAD4: return quad4;
    case QUAD8: return quad8;
    default: return quad9;
  }
}

// Monomial exponents (p, q) of xi^p eta^q spanning each element's space.
inline const int (*monomial_exponents(int t))[2] {
  static const int tri3[3][2] = {{0, 0}, {1, 0}, {0, 1}};
  static const int tri6[6][2] = {{0, 0}, {1, 0}, {0, 1}, {2, 0}, {1, 1}, {0, 2}};
  static const int quad4[4][2] = {{0, 0}, {1, 0}, {0, 1}, {1, 1}};
  static const int quad8[8][2] = {{0, 0}, {1, 0}, {0, 1}, {2, 0},
                                  {1, 1}, {0, 2}, {2, 1}, {1, 2}};
  static const int quad9[9][2] = {{0, 0}, {1, 0}, {0, 1}, {2, 0}, {1, 1},
                                  {0, 2}, {2, 1}, {1, 2}, {2, 2}};
  return by_type(t, tri3, tri6, quad4, quad8, quad9);
}

// Reference node positions in local coordinates.
inline const double (*reference_nodes(int t))[2] {
  static const double tri3[3][2] = {{0, 0}, {1, 0}, {0, 1}};
  static const double tri6[6][2] = {{0, 0}, {1, 0}, {0, 1}, {0.5, 0}, {0.5, 0.5}, {0, 0.5}};
  static const double quad4[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
  static const double quad8[8][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1},
                                     {0, -1},  {1, 0},  {0, 1}, {-1, 0}};
  static const double quad9[9][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}, {0, -1},
                                     {1, 0},   {0, 1},  {-1, 0}, {0, 0}};
  return by_type(t, tri3, tri6, quad4, quad8, quad9);
}

// Monomials and their derivatives at (xi, eta).
inline void eval_monomials(int t, double xi, double eta, double* m, double* dm_dxi,
                           double* dm_deta) {
  const int n = nodes_per_element(t);
  const auto* e = monomial_exponents(t);
  double px[3] = {1.0, xi, xi * xi};
  double py[3] = {1.0, eta, eta * eta};
  for (int k = 0; k < n; ++k) {
    const int p = e[k][0], q = e[k][1];
    m[k] = px[p] * py[q];
    if (dm_dxi) {
      dm_dxi[k] = p == 0 ? 0.0 : p * px[p - 1] * py[q];
      dm_deta[k] = q == 0 ? 0.0 : q * px[p] * py[q - 1];
    }
  }
}

// Inverts the n x n Vandermonde matrix V[k][m] = monomial_m(points_k) into
// coeff (row-major n x n, basis_k(x) = sum_m monomial_m(x) coeff[m*n + k]).
// Returns the smallest pivot magnitude relative to the largest entry (0 if
// the points are not unisolvent).
inline double lagrange_coefficients(int t, const double (*points)[2], double* coeff) {
  const int n = nodes_per_element(t);
  double a[kMaxNodes][2 * kMaxNodes];
  double scale = 0.0;
  for (int k = 0; k < n; ++k) {
    double m[kMaxNodes];
    eval_monomials(t, points[k][0], points[k][1], m, nullptr, nullptr);
    for (int j = 0; j < n; ++j) {
      a[k][j] = m[j];
      a[k][n + j] = (j == k) ? 1.0 : 0.0;
      scale = std::fmax(scale, std::fabs(m[j]));
    }
  }
  double min_pivot = INFINITY;
  for (int c = 0; c < n; ++c) {
    int piv = c;
    for (int r = c + 1; r < n; ++r)
      if (std::fabs(a[r][c]) > std::fabs(a[piv][c])) piv = r;
    if (piv != c)
      for (int j = 0; j < 2 * n; ++j) std::swap(a[c][j], a[piv][j]);
    const double d = a[c][c];
    min_pivot = std::fmin(min_pivot, std::fabs(d));
    if (d == 0.0) return 0.0;
    for (int j = 0; j < 2 * n; ++j) a[c][j] /= d;
    for (int r = 0; r < n; ++r) {
      if (r == c) continue;
      const double f = a[r][c];
      if (f != 0.0)
        for (int j = 0; j < 2 * n; ++j) a[r][j] -= f * a[c][j];
    }
  }
  // a[:, n:] = V^{-1}; basis_k = sum_m mono_m * Vinv[m][k].
  for (int mrow = 0; mrow < n; ++mrow)
    for (int k = 0; k < n; ++k) coeff[mrow * n + k] = a[mrow][n + k];
  return scale > 0 ? min_pivot / scale : 0.0;
}

// Geometric basis coefficients of each element type (computed once).
struct GeometricBases {
  double coeff[5][kMaxNodes * kMaxNodes];
  GeometricBases() {
    for (int t = 0; t < 5; ++t) lagrange_coefficients(t, reference_nodes(t), coeff[t]);
  }
};
inline const GeometricBases& geometric_bases() {
  static const GeometricBases g;
  return g;
}

// Basis values (and optionally derivatives) from a coefficient matrix.
inline void eval_basis(int t, const double* coeff, double xi, double eta, double* N,
                       double* dN_dxi, double* dN_deta) {
  const int n = nodes_per_element(t);
  double m[kMaxNodes], mx[kMaxNodes], my[kMaxNodes];
  eval_monomials(t, xi, eta, m, dN_dxi ? mx : nullptr, dN_dxi ? my : nullptr);
  for (int k = 0; k < n; ++k) {
    double s = 0.0, sx = 0.0, sy = 0.0;
    for (int j = 0; j < n; ++j) {
      const double c = coeff[j * n + k];
      s += m[j] * c;
      if (dN_dxi) {
        sx += mx[j] * c;
        sy += my[j] * c;
      }
    }
    N[k] = s;
    if (dN_dxi) {
      dN_dxi[k] = sx;
      dN_deta[k] = sy;
    }
  }
}

// Position, unit normal and surface Jacobian at a local point.
struct SurfacePoint {
  double x[3];
  double n[3];
  double jac;
};

inline SurfacePoint map_point(int t, const double (*X)[3], double xi, double eta) {
  const int n = nodes_per_element(t);
  double N[kMaxNodes], Nx[kMaxNodes], Ny[kMaxNodes];
  eval_basis(t, geometric_bases().coeff[t], xi, eta, N, Nx, Ny);
  SurfacePoint p{};
  double a[3] = {0, 0, 0}, b[3] = {0, 0, 0};
  for (int k = 0; k < n; ++k)
    for (int d = 0; d < 3; ++d) {
      p.x[d] += N[k] * X[k][d];
      a[d] += Nx[k] * X[k][d];
      b[d] += Ny[k] * X[k][d];
    }
  const double c[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                       a[0] * b[1] - a[1] * b[0]};
  p.jac = std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
  const double inv = p.jac > 0 ? 1.0 / p.jac : 0.0;
  for (int d = 0; d < 3; ++d) p.n[d] = c[d] * inv;
  return p;
}

}  // namespace bemcontact
