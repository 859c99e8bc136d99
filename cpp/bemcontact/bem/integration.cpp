// Element integration (see integration.hpp).
#include "bem/integration.hpp"
#include "parallel.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace bemcontact {

namespace {

inline double dist(const double* a, const double* b) {
  const double d0 = a[0] - b[0], d1 = a[1] - b[1], d2 = a[2] - b[2];
  return std::sqrt(d0 * d0 + d1 * d1 + d2 * d2);
}

// Gauss order per direction for a smooth-but-nearly-singular integrand whose
// singularity sits at relative distance R = d / L from an element of size L:
// the Gauss error decays like rho^(-2n), rho the Bernstein ellipse parameter
// of a singularity at distance 2R (in half-lengths) from the interval.
inline int regular_order(double R, const QuadratureParams& q) {
  // order <= o  <=>  n <= o  <=>  rho >= rho_o = exp(log(1/tol) / (2 (o - 1)))
  // <=>  R >= R_o = (rho_o - 1/rho_o) / 4: thresholds computed once per thread
  // and settings (this runs for every element-point pair)
  thread_local double tol = -1.0;
  thread_local int lo = -1, hi = -1;
  thread_local double thr[kMaxGaussOrder + 2];
  if (q.tolerance != tol || q.min_order != lo || q.max_order != hi) {
    tol = q.tolerance;
    lo = q.min_order;
    hi = q.max_order;
    for (int o = 2; o <= std::min(hi, kMaxGaussOrder); ++o) {
      const double rho = std::exp(std::log(1.0 / tol) / (2.0 * (o - 1)));
      thr[o] = 0.25 * (rho - 1.0 / rho);
    }
  }
  if (!(R > 0.0)) return hi + 1;
  for (int o = std::max(lo, 2); o <= std::min(hi, kMaxGaussOrder); ++o)
    if (R >= thr[o]) return o;
  return hi + 1;
}

// Element integration, vectorized over quadrature points.  A point set is
// stored as structure of arrays with stride `np` (its number of points): x, y,
// z, nx, ny, nz, w*J, then the n basis values point by point (np x n).  The
// kernels are reduced per point to kTerms scalars (Kelvin U: 1 isotropic + 6
// symmetric dyadic terms; T: 1 isotropic + 6 symmetric + 3 antisymmetric;
// point_terms, bem/kernels.hpp), accumulated against the basis values (a
// (kTerms x np) by (np x n) product, n a compile-time constant for the usual
// element types), then expanded into the 3 x 3n blocks (expand_terms).
// Points are taken in chunks of kChunk.
constexpr int kSoaFields = 7;

// acc (kTerms x n) += q (kTerms x cnt) * phi (cnt x n, row p contiguous):
// point by point, a broadcast of q[m][p] times the n basis values.
template <int N>
inline void contract_terms(const double* q, const double* phi, size_t cnt, int n, double* acc) {
  const int nn = N > 0 ? N : n;
  for (size_t p = 0; p < cnt; ++p) {
    const double* ph = phi + p * nn;
    for (int m = 0; m < kTerms; ++m) {
      const double qm = q[m * kChunk + p];
#pragma omp simd
      for (int k = 0; k < nn; ++k) acc[m * nn + k] += qm * ph[k];
    }
  }
}

// Integrate the point set c (np points) of an element with n functional nodes.
void integrate_points(const double* c, size_t np, int n, const double* x, int skip,
                      const Kelvin& K, bool want_h, bool want_g, double* He, double* Ge) {
  alignas(64) double q[kTerms * kChunk];
  double acc[kTerms * kMaxNodes] = {};
  const double* phi = c + kSoaFields * np;
  for (size_t p0 = 0; p0 < np; p0 += kChunk) {
    const size_t cnt = std::min(kChunk, np - p0);
    point_terms(c, np, p0, cnt, x, K, want_h, want_g, q);
    const double* ph = phi + p0 * n;
    switch (n) {
      case 3: contract_terms<3>(q, ph, cnt, 3, acc); break;
      case 4: contract_terms<4>(q, ph, cnt, 4, acc); break;
      case 6: contract_terms<6>(q, ph, cnt, 6, acc); break;
      case 8: contract_terms<8>(q, ph, cnt, 8, acc); break;
      case 9: contract_terms<9>(q, ph, cnt, 9, acc); break;
      default: contract_terms<0>(q, ph, cnt, n, acc); break;
    }
  }
  expand_terms(acc, n, skip, K, want_h, want_g, He, Ge);
}

// The element type of a node count (3 tri3, 4 quad4, 6 tri6, 8 quad8, 9
// quad9): a compile-time constant, so eval_monomials unrolls.
template <int N>
constexpr int type_of() {
  return N == 3 ? TRI3 : N == 4 ? QUAD4 : N == 6 ? TRI6 : N == 8 ? QUAD8 : QUAD9;
}

template <int N>
void map_rule_n(const Element& e, const Rule2D& rule, double* out) {
  const size_t np = rule.size();
  for (size_t p = 0; p < np; ++p) {
    double m[N], mx[N], my[N];
    eval_monomials(type_of<N>(), rule.xi[p], rule.eta[p], m, mx, my);
    double x[3] = {0, 0, 0}, a[3] = {0, 0, 0}, b[3] = {0, 0, 0};
    for (int k = 0; k < N; ++k)
      for (int d = 0; d < 3; ++d) {
        x[d] += m[k] * e.gm[k][d];
        a[d] += mx[k] * e.gm[k][d];
        b[d] += my[k] * e.gm[k][d];
      }
    const double c[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                         a[0] * b[1] - a[1] * b[0]};
    const double jac = std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
    const double inv = jac > 0 ? 1.0 / jac : 0.0;
    for (int d = 0; d < 3; ++d) {
      out[d * np + p] = x[d];
      out[(3 + d) * np + p] = c[d] * inv;
    }
    out[6 * np + p] = rule.w[p] * jac;
    double* phi = out + kSoaFields * np + p * N;
    for (int k = 0; k < N; ++k) {
      double s = 0.0;
      for (int j = 0; j < N; ++j) s += m[j] * e.cf[j * N + k];
      phi[k] = s;
    }
  }
}

// The point set of a local rule on element e, into `out` (see integrate_points).
void map_rule(const Element& e, const Rule2D& rule, std::vector<double>& out) {
  out.resize(rule.size() * (kSoaFields + e.n));
  switch (e.n) {
    case 3: map_rule_n<3>(e, rule, out.data()); break;
    case 4: map_rule_n<4>(e, rule, out.data()); break;
    case 6: map_rule_n<6>(e, rule, out.data()); break;
    case 8: map_rule_n<8>(e, rule, out.data()); break;
    default: map_rule_n<9>(e, rule, out.data()); break;
  }
}

// Position only, from the monomial form.
inline void map_position(const Element& e, double xi, double eta, double* x) {
  double m[kMaxNodes];
  eval_monomials(e.type, xi, eta, m, nullptr, nullptr);
  x[0] = x[1] = x[2] = 0.0;
  for (int k = 0; k < e.n; ++k)
    for (int d = 0; d < 3; ++d) x[d] += m[k] * e.gm[k][d];
}

// Integrate with an explicit local rule (points in the element's reference domain).
void integrate_rule(const Element& e, const Rule2D& rule, const double* x, int skip,
                    const Kelvin& K, bool want_h, bool want_g, double* He, double* Ge) {
  thread_local std::vector<double> buf;
  map_rule(e, rule, buf);
  integrate_points(buf.data(), rule.size(), e.n, x, skip, K, want_h, want_g, He, Ge);
}

void integrate_cached(const Element& e, int order, const double* x, const Kelvin& K,
                      bool want_h, bool want_g, double* He, double* Ge) {
  const std::vector<double>& c = e.cache[order];
  integrate_points(c.data(), c.size() / (kSoaFields + e.n), e.n, x, -1, K, want_h, want_g, He,
                   Ge);
}

// A parametric sub-domain of an element: an axis-aligned rectangle (quads) or
// a triangle (triangles).
struct SubDomain {
  double p[3][2];  // triangle vertices, or p[0] = (u0, v0), p[1] = (u1, v1)
};

void subdomain_geometry(const Element& e, const SubDomain& s, const double* x, double& dmin,
                        double& diam) {
  // sample a 5x5 parametric grid; diameter from the corners
  double pts[25][3];
  int np = 0;
  const bool tri = is_triangle(e.type);
  for (int i = 0; i <= 4; ++i)
    for (int j = 0; j <= 4; ++j) {
      double a, b;
      if (tri) {
        if (i + j > 4) continue;
        const double s1 = i / 4.0, s2 = j / 4.0;
        a = s.p[0][0] + s1 * (s.p[1][0] - s.p[0][0]) + s2 * (s.p[2][0] - s.p[0][0]);
        b = s.p[0][1] + s1 * (s.p[1][1] - s.p[0][1]) + s2 * (s.p[2][1] - s.p[0][1]);
      } else {
        a = s.p[0][0] + (s.p[1][0] - s.p[0][0]) * i / 4.0;
        b = s.p[0][1] + (s.p[1][1] - s.p[0][1]) * j / 4.0;
      }
      map_position(e, a, b, pts[np++]);
    }
  dmin = INFINITY;
  diam = 0.0;
  for (int k = 0; k < np; ++k) {
    dmin = std::min(dmin, dist(pts[k], x));
    for (int l = 0; l < k; ++l) diam = std::max(diam, dist(pts[k], pts[l]));
  }
}

void integrate_adaptive(const Element& e, const SubDomain& s, const double* x, int depth,
                        const Kelvin& K, const QuadratureParams& q, bool want_h,
                        bool want_g, double* He, double* Ge, Rule2D& scratch) {
  double dmin, diam;
  subdomain_geometry(e, s, x, dmin, diam);
  // the 5x5 sample overestimates the distance by at most ~0.18 diam
  const double R = std::max(dmin / diam - 0.2, 0.0);
  const int order = regular_order(R, q);
  const bool tri = is_triangle(e.type);
  if (order <= q.max_order || depth >= q.max_depth) {
    const int o = std::min(order, q.max_order);
    if (depth == 0 && o < static_cast<int>(e.cache.size())) {
      // the whole element: its cached rule holds the same points
      integrate_cached(e, o, x, K, want_h, want_g, He, Ge);
      return;
    }
    scratch.xi.clear();
    scratch.eta.clear();
    scratch.w.clear();
    if (tri)
      append_triangle_rule(scratch, o, o, s.p[0], s.p[1], s.p[2]);
    else
      append_rectangle_rule(scratch, o, s.p[0][0], s.p[1][0], s.p[0][1], s.p[1][1]);
    integrate_rule(e, scratch, x, -1, K, want_h, want_g, He, Ge);
    return;
  }
  SubDomain c[4];
  if (tri) {
    double m01[2], m12[2], m20[2];
    for (int d = 0; d < 2; ++d) {
      m01[d] = 0.5 * (s.p[0][d] + s.p[1][d]);
      m12[d] = 0.5 * (s.p[1][d] + s.p[2][d]);
      m20[d] = 0.5 * (s.p[2][d] + s.p[0][d]);
    }
    const double* v[4][3] = {{s.p[0], m01, m20}, {m01, s.p[1], m12}, {m20, m12, s.p[2]},
                             {m12, m20, m01}};
    for (int k = 0; k < 4; ++k)
      for (int l = 0; l < 3; ++l)
        for (int d = 0; d < 2; ++d) c[k].p[l][d] = v[k][l][d];
  } else {
    const double um = 0.5 * (s.p[0][0] + s.p[1][0]), vm = 0.5 * (s.p[0][1] + s.p[1][1]);
    const double us[3] = {s.p[0][0], um, s.p[1][0]}, vs[3] = {s.p[0][1], vm, s.p[1][1]};
    int k = 0;
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j, ++k) {
        c[k].p[0][0] = us[i];
        c[k].p[1][0] = us[i + 1];
        c[k].p[0][1] = vs[j];
        c[k].p[1][1] = vs[j + 1];
      }
  }
  for (int k = 0; k < 4; ++k)
    integrate_adaptive(e, c[k], x, depth + 1, K, q, want_h, want_g, He, Ge, scratch);
}

inline const double (*corner_coords(int t))[2] {
  static const double tri[3][2] = {{0, 0}, {1, 0}, {0, 1}};
  static const double quad[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
  return is_triangle(t) ? tri : quad;
}

// Polar (Duffy) rule around the local point xi0: one collapsed sub-triangle
// (xi0, P, Q) per piece PQ of each element side not containing xi0.  A side is
// bisected until every piece spans at most q.max_angle seen from xi0 and is
// no longer than its distance to xi0; then the integrand's nearest complex
// singularity in the Duffy angular parameter lies at least about one piece
// length away, and Gauss converges geometrically (same order as the regular
// rule).  Equal-angle splitting alone leaves grazing pieces badly resolved.
void append_polar_piece(const Element& el, const double* xi0, const double* x0,
                        const double* P, const double* Q, const QuadratureParams& q, int depth,
                        Rule2D& rule) {
  // criteria in physical space (the map may be far from affine): the angle
  // the piece subtends at x0, its chord length, and its distance to x0
  const SurfacePoint sp = map_point(el.type, el.X, P[0], P[1]);
  const SurfacePoint sq = map_point(el.type, el.X, Q[0], Q[1]);
  double vp[3], vq[3], e[3];
  for (int d = 0; d < 3; ++d) {
    vp[d] = sp.x[d] - x0[d];
    vq[d] = sq.x[d] - x0[d];
    e[d] = sq.x[d] - sp.x[d];
  }
  const double len2 = e[0] * e[0] + e[1] * e[1] + e[2] * e[2];
  const double len = std::sqrt(len2);
  const double c[3] = {vp[1] * vq[2] - vp[2] * vq[1], vp[2] * vq[0] - vp[0] * vq[2],
                       vp[0] * vq[1] - vp[1] * vq[0]};
  const double ang = std::atan2(std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]),
                                vp[0] * vq[0] + vp[1] * vq[1] + vp[2] * vq[2]);
  double t = -(vp[0] * e[0] + vp[1] * e[1] + vp[2] * e[2]) / len2;
  t = std::min(1.0, std::max(0.0, t));
  double dseg = 0.0;
  for (int d = 0; d < 3; ++d) dseg += (vp[d] + t * e[d]) * (vp[d] + t * e[d]);
  dseg = std::sqrt(dseg);
  if (depth < 12 && (ang > q.max_angle || len > 0.5 * dseg)) {
    const double M[2] = {0.5 * (P[0] + Q[0]), 0.5 * (P[1] + Q[1])};
    append_polar_piece(el, xi0, x0, P, M, q, depth + 1, rule);
    append_polar_piece(el, xi0, x0, M, Q, q, depth + 1, rule);
    return;
  }
  append_triangle_rule(rule, q.singular_order, q.singular_order, xi0, P, Q);
}

void singular_rule(const Element& e, const double* xi0, const QuadratureParams& q,
                   Rule2D& rule) {
  const int nc = n_corners(e.type);
  const auto* c = corner_coords(e.type);
  const SurfacePoint x0 = map_point(e.type, e.X, xi0[0], xi0[1]);
  for (int s = 0; s < nc; ++s) {
    const double* A = c[s];
    const double* B = c[(s + 1) % nc];
    const double va[2] = {A[0] - xi0[0], A[1] - xi0[1]};
    const double vb[2] = {B[0] - xi0[0], B[1] - xi0[1]};
    const double e0 = B[0] - A[0], e1 = B[1] - A[1];
    const double len = std::sqrt(e0 * e0 + e1 * e1);
    const double cr = va[0] * vb[1] - va[1] * vb[0];
    if (std::fabs(cr) / len <= 1e-13) continue;  // xi0 on this side
    append_polar_piece(e, xi0, x0.x, A, B, q, 0, rule);
  }
}

}  // namespace

std::vector<Element> prepare_elements(const MeshView& m, int max_cached_order, int threads) {
  std::vector<Element> els(m.n_elements);
  ExceptionGuard guard;
#pragma omp parallel for schedule(static) num_threads(threads)
  for (int64_t ie = 0; ie < m.n_elements; ++ie) guard.run([&] {
    Element& e = els[ie];
    e.type = m.etype[ie];
    e.n = nodes_per_element(e.type);
    for (int k = 0; k < e.n; ++k) {
      const int64_t g = m.conn[ie * kMaxNodes + k];
      for (int d = 0; d < 3; ++d) e.X[k][d] = m.nodes[3 * g + d];
      e.f[k] = m.fconn[ie * kMaxNodes + k];
      e.fxi[k][0] = m.fxi[(ie * kMaxNodes + k) * 2];
      e.fxi[k][1] = m.fxi[(ie * kMaxNodes + k) * 2 + 1];
    }
    lagrange_coefficients(e.type, e.fxi, e.cf);
    {
      const double* gc = geometric_bases().coeff[e.type];
      for (int mo = 0; mo < e.n; ++mo)
        for (int d = 0; d < 3; ++d) {
          double v = 0.0;
          for (int k = 0; k < e.n; ++k) v += gc[mo * e.n + k] * e.X[k][d];
          e.gm[mo][d] = v;
        }
    }
    for (int d = 0; d < 3; ++d) {
      e.centroid[d] = 0.0;
      for (int k = 0; k < e.n; ++k) e.centroid[d] += e.X[k][d];
      e.centroid[d] /= e.n;
    }
    e.radius = 0.0;
    e.diam = 0.0;
    for (int k = 0; k < e.n; ++k) {
      e.radius = std::max(e.radius, dist(e.X[k], e.centroid));
      for (int l = 0; l < k; ++l) e.diam = std::max(e.diam, dist(e.X[k], e.X[l]));
    }
    // curved elements bulge: pad the radius a little
    e.radius *= 1.1;
    e.cache.assign(max_cached_order + 1, {});
    Rule2D r;
    for (int o = 1; o <= max_cached_order; ++o) {
      r.xi.clear();
      r.eta.clear();
      r.w.clear();
      if (is_triangle(e.type)) {
        const double A[2] = {0, 0}, B[2] = {1, 0}, C[2] = {0, 1};
        append_triangle_rule(r, o, o, A, B, C);
      } else {
        append_rectangle_rule(r, o, -1, 1, -1, 1);
      }
      map_rule(e, r, e.cache[o]);
    }
  });
  guard.rethrow();
  return els;
}

void element_influence(const Element& e, const double* x, int local, const Kelvin& K,
                       const QuadratureParams& q, bool want_h, bool want_g, double* He,
                       double* Ge) {
  Rule2D rule;
  if (local >= 0) {
    singular_rule(e, e.fxi[local], q, rule);
    integrate_rule(e, rule, x, local, K, want_h, want_g, He, Ge);
    return;
  }
  // cheap bound first: distance to the bounding sphere
  const double dc = dist(x, e.centroid);
  const int max_cached = static_cast<int>(e.cache.size()) - 1;
  if (dc - e.radius > 1.5 * e.diam) {
    const double R = (dc - e.radius) / e.diam;
    const int o = regular_order(R, q);
    if (o <= max_cached && o <= q.max_order) {
      integrate_cached(e, o, x, K, want_h, want_g, He, Ge);
      return;
    }
    if (o <= q.max_order) {  // the whole element, a rule beyond the cache
      if (is_triangle(e.type)) {
        const double A[2] = {0, 0}, B[2] = {1, 0}, C[2] = {0, 1};
        append_triangle_rule(rule, o, o, A, B, C);
      } else {
        append_rectangle_rule(rule, o, -1, 1, -1, 1);
      }
      integrate_rule(e, rule, x, -1, K, want_h, want_g, He, Ge);
      return;
    }
  }
  SubDomain root;
  if (is_triangle(e.type)) {
    const double v[3][2] = {{0, 0}, {1, 0}, {0, 1}};
    std::memcpy(root.p, v, sizeof(v));
  } else {
    root.p[0][0] = -1;
    root.p[0][1] = -1;
    root.p[1][0] = 1;
    root.p[1][1] = 1;
  }
  integrate_adaptive(e, root, x, 0, K, q, want_h, want_g, He, Ge, rule);
}

}  // namespace bemcontact
