#include "operators.hpp"

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
  if (R <= 0.0) return q.max_order + 1;
  const double beta = 2.0 * R;
  const double rho = beta + std::sqrt(beta * beta + 1.0);
  const double n = std::log(1.0 / q.tolerance) / (2.0 * std::log(rho)) + 1.0;
  // (a tiny R gives a huge n: cap before converting, int overflow would wrap)
  if (!(n < q.max_order + 1.0)) return q.max_order + 1;
  int o = static_cast<int>(std::ceil(n));
  return std::max(o, q.min_order);
}

// Kernel accumulation at one quadrature point y (normal ny, weight w*J,
// functional basis phi).
inline void accumulate(const double* x, const double* y, const double* ny, double wj,
                       const double* phi, int n, int skip, const Kelvin& K, bool want_h,
                       bool want_g, double* He, double* Ge) {
  const double r0 = y[0] - x[0], r1 = y[1] - x[1], r2 = y[2] - x[2];
  const double r = std::sqrt(r0 * r0 + r1 * r1 + r2 * r2);
  const double ir = 1.0 / r;
  const double d[3] = {r0 * ir, r1 * ir, r2 * ir};
  const int ld = 3 * n;
  if (want_g) {
    double U[3][3];
    const double c = K.c1 * ir * wj;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) U[i][j] = c * ((i == j ? K.a : 0.0) + d[i] * d[j]);
    for (int k = 0; k < n; ++k) {
      const double p = phi[k];
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) Ge[i * ld + 3 * k + j] += U[i][j] * p;
    }
  }
  if (want_h) {
    double T[3][3];
    const double drdn = d[0] * ny[0] + d[1] * ny[1] + d[2] * ny[2];
    const double c = -K.c2 * ir * ir * wj;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        T[i][j] = c * (drdn * ((i == j ? K.b : 0.0) + 3.0 * d[i] * d[j]) -
                       K.b * (d[i] * ny[j] - d[j] * ny[i]));
    for (int k = 0; k < n; ++k) {
      if (k == skip) continue;
      const double p = phi[k];
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) He[i * ld + 3 * k + j] += T[i][j] * p;
    }
  }
}

// Integrate with an explicit local rule (points in the element's reference domain).
void integrate_rule(const Element& e, const Rule2D& rule, const double* x, int skip,
                    const Kelvin& K, bool want_h, bool want_g, double* He, double* Ge) {
  double phi[kMaxNodes];
  for (size_t p = 0; p < rule.size(); ++p) {
    const SurfacePoint sp = map_point(e.type, e.X, rule.xi[p], rule.eta[p]);
    eval_basis(e.type, e.cf, rule.xi[p], rule.eta[p], phi, nullptr, nullptr);
    accumulate(x, sp.x, sp.n, rule.w[p] * sp.jac, phi, e.n, skip, K, want_h, want_g, He,
               Ge);
  }
}

void integrate_cached(const Element& e, int order, const double* x, const Kelvin& K,
                      bool want_h, bool want_g, double* He, double* Ge) {
  const std::vector<double>& c = e.cache[order];
  const int stride = 7 + e.n;
  const size_t np = c.size() / stride;
  for (size_t p = 0; p < np; ++p) {
    const double* q = c.data() + p * stride;
    accumulate(x, q, q + 3, q[6], q + 7, e.n, -1, K, want_h, want_g, He, Ge);
  }
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
      const SurfacePoint sp = map_point(e.type, e.X, a, b);
      std::memcpy(pts[np++], sp.x, sizeof(sp.x));
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
#pragma omp parallel for schedule(static) num_threads(threads)
  for (int64_t ie = 0; ie < m.n_elements; ++ie) {
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
      std::vector<double>& c = e.cache[o];
      c.resize(r.size() * (7 + e.n));
      for (size_t p = 0; p < r.size(); ++p) {
        double* out = c.data() + p * (7 + e.n);
        const SurfacePoint sp = map_point(e.type, e.X, r.xi[p], r.eta[p]);
        std::memcpy(out, sp.x, 3 * sizeof(double));
        std::memcpy(out + 3, sp.n, 3 * sizeof(double));
        out[6] = r.w[p] * sp.jac;
        eval_basis(e.type, e.cf, r.xi[p], r.eta[p], out + 7, nullptr, nullptr);
      }
    }
  }
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
#pragma omp parallel for schedule(dynamic, 4) num_threads(threads)
  for (int64_t i = 0; i < n_points; ++i)
    influence_rows(els, i, points + 3 * i, K, q, ncol, H + 3 * i * ncol, G + 3 * i * ncol);
}

void assemble_system(const MeshView& m, const double* points, int64_t n_points,
                     double shear_modulus, double nu, const QuadratureParams& q,
                     const uint8_t* known_u, const double* W, int64_t s, const int64_t* bcols,
                     int64_t nb, int threads, double* A, int64_t lda, double* BW, double* BC) {
  const std::vector<Element> els = prepare_elements(m, std::min(q.max_order, kMaxCachedOrder), threads);
  const Kelvin K(shear_modulus, nu);
  const int64_t ncol = 3 * n_points;
#pragma omp parallel num_threads(threads)
  {
    std::vector<double> Hrow(3 * ncol), Grow(3 * ncol);
#pragma omp for schedule(dynamic, 4)
    for (int64_t i = 0; i < n_points; ++i) {
      influence_rows(els, i, points + 3 * i, K, q, ncol, Hrow.data(), Grow.data());
      for (int r = 0; r < 3; ++r) {
        const double* h = Hrow.data() + r * ncol;
        const double* g = Grow.data() + r * ncol;
        const int64_t row = 3 * i + r;
        // A column-major (leading dimension lda): A[row, c]
        for (int64_t c = 0; c < ncol; ++c) A[row + lda * c] = known_u[c] ? -g[c] : h[c];
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
    }
  }
}

}  // namespace bemcontact
