// Somigliana's identity at interior points (see interior.hpp and the
// docstring of bemcontact.bem.interior for the formulas).
#include "bem/interior.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

#include "bem/element.hpp"
#include "parallel.hpp"

namespace bemcontact {

namespace {

// the smallest Gauss order, and the orders added to the estimate
constexpr int kMinOrder = 2;
constexpr int kExtra = 1;
// A piece's distance is its sampled distance minus this fraction of its
// diameter (3 x 3 samples of a quadrilateral leave no point farther than 1/4
// of the diameter from a sample; the 7 samples of a triangle, 0.16).
constexpr double kSafety = 0.25;
// Per Gauss point: y (3), n J w (3), J w, u (3), t (3); a block holds the
// rows of Q points one after the other.
constexpr int kFields = 13;
constexpr int kMaxQ = kMaxInteriorOrder * kMaxInteriorOrder;
// Newton steps of the nearest-point search, at most, and the step (in local
// coordinates) below which it has converged
constexpr int kNewtonSteps = 12;
constexpr double kNewtonStop = 1e-14;
// points integrated together (sharing each element's rule in cache)
constexpr int kBatch = 8;

// The Somigliana integrand of the Q points of a block seen from x, with u0
// subtracted from their displacements, added to acc: the stress (6) or the
// displacement (3), both without the common factor 1 / (8 pi (1 - nu)).
// Stress, with r = y - x, d = r / |r|, n = n J w, u = u - u0, b = 1 - 2 nu:
//   sigma_ij += A d_i d_j + v_i d_j + v_j d_i - 2G b / |r|^3 (n_j u_i + n_i u_j) + C delta_ij
//   (v_i = J w b t_i / |r|^2 - 6 nu G / |r|^3 (dn u_i + du n_i), dn = d . n, du = d . u)
// (the D t - S u of the docstring, its terms collected).  Displacement:
//   u_i += U*_ij t_j - T*_ij u_j.
template <bool kStress>
inline void accumulate(const double* blk, int Q, const double* x, const double* u0, double G,
                       double nu, double* acc) {
  const double* y0 = blk;
  const double* y1 = blk + Q;
  const double* y2 = blk + 2 * Q;
  const double* n0 = blk + 3 * Q;
  const double* n1 = blk + 4 * Q;
  const double* n2 = blk + 5 * Q;
  const double* jw = blk + 6 * Q;
  const double* f0 = blk + 7 * Q;
  const double* f1 = blk + 8 * Q;
  const double* f2 = blk + 9 * Q;
  const double* t0 = blk + 10 * Q;
  const double* t1 = blk + 11 * Q;
  const double* t2 = blk + 12 * Q;
  const double x0 = x[0], x1 = x[1], x2 = x[2];
  const double v0 = u0[0], v1 = u0[1], v2 = u0[2];
  const double b = 1.0 - 2.0 * nu;
  double s0 = 0, s1 = 0, s2 = 0, s3 = 0, s4 = 0, s5 = 0, sc = 0;
  if constexpr (kStress) {
    const double g2 = 2.0 * G, c4 = 1.0 - 4.0 * nu;
#pragma omp simd reduction(+ : s0, s1, s2, s3, s4, s5, sc)
    for (int q = 0; q < Q; ++q) {
      const double r0 = y0[q] - x0, r1 = y1[q] - x1, r2 = y2[q] - x2;
      const double ir = 1.0 / std::sqrt(r0 * r0 + r1 * r1 + r2 * r2);
      const double d0 = r0 * ir, d1 = r1 * ir, d2 = r2 * ir;
      const double u0q = f0[q] - v0, u1q = f1[q] - v1, u2q = f2[q] - v2;
      const double du = d0 * u0q + d1 * u1q + d2 * u2q;
      const double dt = d0 * t0[q] + d1 * t1[q] + d2 * t2[q];
      const double dn = d0 * n0[q] + d1 * n1[q] + d2 * n2[q];
      const double nu_ = n0[q] * u0q + n1[q] * u1q + n2[q] * u2q;
      const double cd = jw[q] * ir * ir;
      const double cs = g2 * ir * ir * ir;
      const double A = 3.0 * cd * dt + cs * (15.0 * dn * du - 3.0 * b * nu_);
      const double C = -cd * b * dt - cs * (3.0 * b * dn * du - c4 * nu_);
      const double Bn = -cs * b;
      const double cdb = cd * b, csn = 3.0 * nu * cs, hA = 0.5 * A;
      // sigma_ij = p_i d_j + p_j d_i + m_i u_j + m_j u_i + C delta_ij,
      // p = A/2 d + v, m = -2G b / |r|^3 n
      const double p0 = hA * d0 + cdb * t0[q] - csn * (dn * u0q + du * n0[q]);
      const double p1 = hA * d1 + cdb * t1[q] - csn * (dn * u1q + du * n1[q]);
      const double p2 = hA * d2 + cdb * t2[q] - csn * (dn * u2q + du * n2[q]);
      const double m0 = Bn * n0[q], m1 = Bn * n1[q], m2 = Bn * n2[q];
      s0 += p0 * d0 + m0 * u0q;  // half the diagonal, less C
      s1 += p1 * d1 + m1 * u1q;
      s2 += p2 * d2 + m2 * u2q;
      sc += C;
      s3 += p0 * d1 + p1 * d0 + m0 * u1q + m1 * u0q;
      s4 += p1 * d2 + p2 * d1 + m1 * u2q + m2 * u1q;
      s5 += p0 * d2 + p2 * d0 + m0 * u2q + m2 * u0q;
    }
    acc[0] += 2.0 * s0 + sc;
    acc[1] += 2.0 * s1 + sc;
    acc[2] += 2.0 * s2 + sc;
    acc[3] += s3;
    acc[4] += s4;
    acc[5] += s5;
  } else {
    const double i2g = 0.5 / G, a = 3.0 - 4.0 * nu;
#pragma omp simd reduction(+ : s0, s1, s2)
    for (int q = 0; q < Q; ++q) {
      const double r0 = y0[q] - x0, r1 = y1[q] - x1, r2 = y2[q] - x2;
      const double ir = 1.0 / std::sqrt(r0 * r0 + r1 * r1 + r2 * r2);
      const double d0 = r0 * ir, d1 = r1 * ir, d2 = r2 * ir;
      const double u0q = f0[q] - v0, u1q = f1[q] - v1, u2q = f2[q] - v2;
      const double du = d0 * u0q + d1 * u1q + d2 * u2q;
      const double dt = d0 * t0[q] + d1 * t1[q] + d2 * t2[q];
      const double dn = d0 * n0[q] + d1 * n1[q] + d2 * n2[q];
      const double nu_ = n0[q] * u0q + n1[q] * u1q + n2[q] * u2q;
      // U* t = J w / (2G |r|) (a t + d (d . t)),
      // -T* u = (dn (b u + 3 d du) - b (d nu_ - n du)) / |r|^2
      const double cu = i2g * jw[q] * ir, ct = ir * ir;
      const double D = cu * dt + ct * (3.0 * dn * du - b * nu_);
      const double ca = cu * a, cb = ct * b * dn, cn = ct * b * du;
      s0 += D * d0 + ca * t0[q] + cb * u0q + cn * n0[q];
      s1 += D * d1 + ca * t1[q] + cb * u1q + cn * n1[q];
      s2 += D * d2 + ca * t2[q] + cb * u2q + cn * n2[q];
    }
    acc[0] += s0;
    acc[1] += s1;
    acc[2] += s2;
  }
}

inline double dist2(const double* a, const double* b) {
  const double r0 = a[0] - b[0], r1 = a[1] - b[1], r2 = a[2] - b[2];
  return r0 * r0 + r1 * r1 + r2 * r2;
}

// The largest distance between n points (n x 3).
inline double diameter(const double* p, int n) {
  double s = 0.0;
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j) s = std::max(s, dist2(p + 3 * i, p + 3 * j));
  return std::sqrt(s);
}

}  // namespace

InteriorEvaluator::InteriorEvaluator(int type, int64_t n_elements, const double* geo,
                                     const double* coef, double shear_modulus, double nu,
                                     double tolerance, int max_order, int max_level)
    : type_(type),
      k_(nodes_per_element(type)),
      m_(n_elements),
      triangle_(is_triangle(type)),
      geo_(geo, geo + n_elements * nodes_per_element(type) * 3),
      coef_(coef, coef + n_elements * nodes_per_element(type) * 6),
      G_(shear_modulus),
      nu_(nu),
      max_order_(max_order),
      max_level_(max_level) {
  if (max_order < kMinOrder || max_order > kMaxInteriorOrder)
    throw std::invalid_argument("InteriorEvaluator: max_order out of range");
  // order n = ceil(ln(1/tol) / (2 ln rho)) + kExtra (at least kMinOrder),
  // rho = beta + sqrt(beta^2 + 1): n <= k  <=>  asinh(beta) >= ln(1/tol) / (2 (k - kExtra))
  for (int k = kMinOrder; k <= max_order; ++k)
    beta_[k] = std::sinh(std::log(1.0 / tolerance) / (2.0 * (k - kExtra)));
  for (int k = kMinOrder; k <= max_order; ++k) {
    if (triangle_) {
      // collapsed Gauss, the collapsed vertex at (1, 0)
      const double A[2] = {1, 0}, B[2] = {0, 0}, C[2] = {0, 1};
      append_triangle_rule(ref_[k], k, k, A, B, C);
    } else {
      append_rectangle_rule(ref_[k], k, -1, 1, -1, 1);
    }
  }
  // samples at which distance and size are taken
  if (triangle_) {
    const double s[7][2] = {{0, 0}, {1, 0}, {0, 1}, {0.5, 0}, {0.5, 0.5}, {0, 0.5},
                            {1.0 / 3, 1.0 / 3}};
    n_samples_ = 7;
    std::copy(&s[0][0], &s[0][0] + 14, &samples_[0][0]);
  } else {
    n_samples_ = 9;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        samples_[3 * i + j][0] = i - 1.0;
        samples_[3 * i + j][1] = j - 1.0;
      }
  }
  const int S = n_samples_;
  far_stride_ = 4 + (max_order - kMinOrder + 1);
  sample_y_.resize(m_ * S * 3);
  size_.resize(m_);
  far_.resize(m_ * far_stride_);
  for (int64_t e = 0; e < m_; ++e) {
    double* ys = sample_y_.data() + e * S * 3;
    double c[3] = {0, 0, 0};
    for (int s = 0; s < S; ++s) {
      map(e, samples_[s][0], samples_[s][1], ys + 3 * s, nullptr, nullptr);
      for (int d = 0; d < 3; ++d) c[d] += ys[3 * s + d] / S;
    }
    double r2 = 0.0;
    for (int s = 0; s < S; ++s) r2 = std::max(r2, dist2(ys + 3 * s, c));
    size_[e] = diameter(ys, S);
    double* f = far_.data() + e * far_stride_;
    f[0] = c[0];
    f[1] = c[1];
    f[2] = c[2];
    f[3] = 1.05 * std::sqrt(r2);
    // bounding sphere: order <= k  <=>  |x - c| - r >= beta_k size / 2
    for (int k = kMinOrder; k <= max_order; ++k) {
      const double t = f[3] + 0.5 * beta_[k] * size_[e];
      f[4 + k - kMinOrder] = t * t;
    }
  }
}

// Position y, n J (the unnormalized normal, if nJ) and fields F (u, t; if F)
// at the local point (xi, eta) of element e.
void InteriorEvaluator::map(int64_t e, double xi, double eta, double* y, double* nJ,
                            double* F) const {
  double M[kMaxNodes], Mx[kMaxNodes], My[kMaxNodes];
  eval_monomials(type_, xi, eta, M, nJ ? Mx : nullptr, nJ ? My : nullptr);
  const double* g = geo_.data() + e * k_ * 3;
  double a[3] = {0, 0, 0}, b[3] = {0, 0, 0};
  y[0] = y[1] = y[2] = 0.0;
  for (int i = 0; i < k_; ++i)
    for (int d = 0; d < 3; ++d) {
      y[d] += M[i] * g[3 * i + d];
      if (nJ) {
        a[d] += Mx[i] * g[3 * i + d];
        b[d] += My[i] * g[3 * i + d];
      }
    }
  if (nJ) {
    nJ[0] = a[1] * b[2] - a[2] * b[1];
    nJ[1] = a[2] * b[0] - a[0] * b[2];
    nJ[2] = a[0] * b[1] - a[1] * b[0];
  }
  if (F) {
    const double* c = coef_.data() + e * k_ * 6;
    for (int d = 0; d < 6; ++d) F[d] = 0.0;
    for (int i = 0; i < k_; ++i)
      for (int d = 0; d < 6; ++d) F[d] += M[i] * c[6 * i + d];
  }
}

// Gauss order per direction for a piece of diameter size at distance d;
// max_order + 1 if it must be cut (d <= 0 or more points needed).
int InteriorEvaluator::order(double d, double size) const {
  if (!(d > 0.0)) return max_order_ + 1;
  const double beta = 2.0 * d / size;
  int k = kMinOrder;
  while (k <= max_order_ && beta < beta_[k]) ++k;
  return k;
}

// The block (kFields rows of Q) of the rule r mapped onto piece p of element e.
void InteriorEvaluator::fill(int64_t e, const Piece& p, const Rule2D& r, double* blk) const {
  const int Q = static_cast<int>(r.size());
  const double det = std::fabs(p.B[0] * p.B[3] - p.B[1] * p.B[2]);
  for (int q = 0; q < Q; ++q) {
    const double xi = p.c[0] + p.B[0] * r.xi[q] + p.B[1] * r.eta[q];
    const double eta = p.c[1] + p.B[2] * r.xi[q] + p.B[3] * r.eta[q];
    double y[3], nJ[3], F[6];
    map(e, xi, eta, y, nJ, F);
    const double w = det * r.w[q];
    for (int d = 0; d < 3; ++d) {
      blk[d * Q + q] = y[d];
      blk[(3 + d) * Q + q] = nJ[d] * w;
    }
    blk[6 * Q + q] = std::sqrt(nJ[0] * nJ[0] + nJ[1] * nJ[1] + nJ[2] * nJ[2]) * w;
    for (int d = 0; d < 6; ++d) blk[(7 + d) * Q + q] = F[d];
  }
}

// The order-k rule on element e: its cached block, filled now if it is
// empty; while another thread fills it, a copy made in scratch.
const double* InteriorEvaluator::element_rule(int64_t e, int k, double* scratch) const {
  RuleCache& c = rules_[k];
  const size_t per = static_cast<size_t>(kFields) * k * k;
  std::call_once(c.once, [&] {
    c.blocks.reset(new double[static_cast<size_t>(m_) * per]);  // pages touched when filled
    c.state.reset(new std::atomic<uint8_t>[m_]());
  });
  double* blk = c.blocks.get() + e * per;
  uint8_t s = c.state[e].load(std::memory_order_acquire);
  if (s == 2) return blk;
  const Piece whole{{0, 0}, {1, 0, 0, 1}};
  if (s == 0 && c.state[e].compare_exchange_strong(s, 1, std::memory_order_acquire)) {
    fill(e, whole, ref_[k], blk);
    c.state[e].store(2, std::memory_order_release);
    return blk;
  }
  fill(e, whole, ref_[k], scratch);
  return scratch;
}

// Piece p of element e at quadtree level `level`: integrated if its order is
// at most max_order (or at the deepest level), else cut into four.
template <bool kStress>
void InteriorEvaluator::quadtree(const double* x, const double* u0, int64_t e, const Piece& p,
                                 int level, double* acc, double* scratch) const {
  const int S = n_samples_;
  double ys[9 * 3];
  double dmin2 = std::numeric_limits<double>::infinity();
  for (int s = 0; s < S; ++s) {
    const double a = samples_[s][0], b = samples_[s][1];
    map(e, p.c[0] + p.B[0] * a + p.B[1] * b, p.c[1] + p.B[2] * a + p.B[3] * b, ys + 3 * s,
        nullptr, nullptr);
    dmin2 = std::min(dmin2, dist2(ys + 3 * s, x));
  }
  const double size = diameter(ys, S);
  const int k = order(std::sqrt(dmin2) - kSafety * size, size);
  if (k <= max_order_ || level == max_level_) {
    const int kk = std::min(k, max_order_);
    const double* blk = scratch;
    if (level == 0)  // the whole element: its shared rule
      blk = element_rule(e, kk, scratch);
    else
      fill(e, p, ref_[kk], scratch);
    accumulate<kStress>(blk, kk * kk, x, u0, G_, nu_, acc);
    return;
  }
  // the four children as affine maps c + B xi_ref of the reference cell
  const double h = 0.5;
  if (triangle_) {
    const double cs[4][2] = {{0, 0}, {0.5, 0}, {0, 0.5}, {0.5, 0.5}};
    for (int i = 0; i < 4; ++i) {
      const double sgn = i == 3 ? -h : h;
      Piece ch;
      ch.c[0] = p.c[0] + p.B[0] * cs[i][0] + p.B[1] * cs[i][1];
      ch.c[1] = p.c[1] + p.B[2] * cs[i][0] + p.B[3] * cs[i][1];
      for (int j = 0; j < 4; ++j) ch.B[j] = p.B[j] * sgn;
      quadtree<kStress>(x, u0, e, ch, level + 1, acc, scratch);
    }
  } else {
    for (int sx = -1; sx <= 1; sx += 2)
      for (int sy = -1; sy <= 1; sy += 2) {
        Piece ch;
        ch.c[0] = p.c[0] + h * (p.B[0] * sx + p.B[1] * sy);
        ch.c[1] = p.c[1] + h * (p.B[2] * sx + p.B[3] * sy);
        for (int j = 0; j < 4; ++j) ch.B[j] = p.B[j] * h;
        quadtree<kStress>(x, u0, e, ch, level + 1, acc, scratch);
      }
  }
}

// A batch of nb <= kBatch points: per element, each point with the order of
// its bounding-sphere distance (those needing more than max_order through the
// quadtree); the points of a batch share each element's rule while it is in
// cache.
template <bool kStress>
void InteriorEvaluator::batch(const double* X, const int64_t* element, const double* xi, int nb,
                              double* out) const {
  double u0[kBatch][3], acc[kBatch][6] = {};
  double scratch[kFields * kMaxQ];  // a piece's rule, or an element's being filled elsewhere
  for (int b = 0; b < nb; ++b) {
    double y[3], F[6];
    map(element[b], xi[2 * b], xi[2 * b + 1], y, nullptr, F);
    for (int d = 0; d < 3; ++d) u0[b][d] = F[d];
  }
  const Piece whole{{0, 0}, {1, 0, 0, 1}};
  for (int64_t e = 0; e < m_; ++e) {
    const double* f = far_.data() + e * far_stride_;
    for (int b = 0; b < nb; ++b) {
      const double* x = X + 3 * b;
      const double r2 = dist2(x, f);
      int k = kMinOrder;
      while (k <= max_order_ && r2 < f[4 + k - kMinOrder]) ++k;
      if (k <= max_order_)
        accumulate<kStress>(element_rule(e, k, scratch), k * k, x, u0[b], G_, nu_, acc[b]);
      else
        quadtree<kStress>(x, u0[b], e, whole, 0, acc[b], scratch);
    }
  }
  const double c0 = 1.0 / (8.0 * M_PI * (1.0 - nu_));
  for (int b = 0; b < nb; ++b) {
    if constexpr (kStress) {
      for (int i = 0; i < 6; ++i) out[6 * b + i] = c0 * acc[b][i];
    } else {
      for (int i = 0; i < 3; ++i) out[3 * b + i] = c0 * acc[b][i] + u0[b][i];
    }
  }
}

void InteriorEvaluator::integrate(const double* X, const int64_t* element, const double* xi,
                                  int64_t n, bool stresses, int threads, double* out) const {
  const int64_t nbatch = (n + kBatch - 1) / kBatch;
  ExceptionGuard guard;
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
  for (int64_t i = 0; i < nbatch; ++i) guard.run([&] {
    const int64_t p = i * kBatch;
    const int nb = static_cast<int>(std::min<int64_t>(kBatch, n - p));
    if (stresses)
      batch<true>(X + 3 * p, element + p, xi + 2 * p, nb, out + 6 * p);
    else
      batch<false>(X + 3 * p, element + p, xi + 2 * p, nb, out + 3 * p);
  });
  guard.rethrow();
}

// The point of element e nearest to x: Gauss-Newton on |y(xi) - x|^2 from
// the element's nearest sample, clamped to the reference cell.
InteriorEvaluator::Candidate InteriorEvaluator::project(int64_t e, const double* x) const {
  const int S = n_samples_;
  const double* ys = sample_y_.data() + e * S * 3;
  int best = 0;
  for (int s = 1; s < S; ++s)
    if (dist2(x, ys + 3 * s) < dist2(x, ys + 3 * best)) best = s;
  double u = samples_[best][0], v = samples_[best][1];
  const double* g = geo_.data() + e * k_ * 3;
  for (int it = 0; it < kNewtonSteps; ++it) {
    double M[kMaxNodes], Mx[kMaxNodes], My[kMaxNodes];
    eval_monomials(type_, u, v, M, Mx, My);
    double a[3] = {0, 0, 0}, b[3] = {0, 0, 0}, r[3] = {-x[0], -x[1], -x[2]};
    for (int i = 0; i < k_; ++i)
      for (int d = 0; d < 3; ++d) {
        r[d] += M[i] * g[3 * i + d];
        a[d] += Mx[i] * g[3 * i + d];
        b[d] += My[i] * g[3 * i + d];
      }
    const double aa = a[0] * a[0] + a[1] * a[1] + a[2] * a[2];
    const double ab = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    const double bb = b[0] * b[0] + b[1] * b[1] + b[2] * b[2];
    const double ga = a[0] * r[0] + a[1] * r[1] + a[2] * r[2];
    const double gb = b[0] * r[0] + b[1] * r[1] + b[2] * r[2];
    const double det = aa * bb - ab * ab;
    const double u_prev = u, v_prev = v;
    u -= (bb * ga - ab * gb) / det;
    v -= (aa * gb - ab * ga) / det;
    if (!triangle_) {
      u = std::clamp(u, -1.0, 1.0);
      v = std::clamp(v, -1.0, 1.0);
    } else {
      u = std::max(u, 0.0);
      v = std::max(v, 0.0);
      if (u + v > 1.0) {
        const double t = std::clamp((u - v + 1.0) / 2.0, 0.0, 1.0);
        u = t;
        v = 1.0 - t;
      }
    }
    if (std::fabs(u - u_prev) <= kNewtonStop && std::fabs(v - v_prev) <= kNewtonStop) break;
  }
  double y[3], nJ[3];
  map(e, u, v, y, nJ, nullptr);
  const double r[3] = {x[0] - y[0], x[1] - y[1], x[2] - y[2]};
  const double d = std::sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
  const double nn = std::sqrt(nJ[0] * nJ[0] + nJ[1] * nJ[1] + nJ[2] * nJ[2]);
  const double c = (r[0] * nJ[0] + r[1] * nJ[1] + r[2] * nJ[2]) / std::max(d * nn, 1e-300);
  return {e, {u, v}, d, c};
}

void InteriorEvaluator::nearest(const double* X, int64_t n, int threads, double* dist,
                                int64_t* element, double* xi, double* cosine) const {
  ExceptionGuard guard;
#pragma omp parallel num_threads(threads)
  {
    std::vector<Candidate> cand;
    std::vector<double> lb(m_);
#pragma omp for schedule(dynamic, 16)
    for (int64_t p = 0; p < n; ++p) guard.run([&] {
      const double* x = X + 3 * p;
      // lower bounds of the elements' distances (their bounding spheres); the
      // element of the smallest projected first, then every element whose
      // bound does not exclude it from being the nearest or tied with it
      int64_t first = 0;
      for (int64_t e = 0; e < m_; ++e) {
        const double* f = far_.data() + e * far_stride_;
        lb[e] = std::sqrt(dist2(x, f)) - f[3];
        if (lb[e] < lb[first]) first = e;
      }
      cand.assign(1, project(first, x));
      double dmin = cand[0].dist;
      for (int64_t e = 0; e < m_; ++e) {
        if (e == first || lb[e] > dmin * (1 + 1e-6) + 1e-12 * size_[e]) continue;
        cand.push_back(project(e, x));
        dmin = std::min(dmin, cand.back().dist);
      }
      // the nearest; among (nearly) equally near elements, the normal most
      // nearly along x - y, then the lowest element number
      const Candidate* pick = nullptr;
      double score = -2.0;
      for (const Candidate& c : cand) {
        const bool tie = c.dist <= dmin * (1 + 1e-6) + 1e-12 * size_[c.e];
        const double sc = tie ? std::fabs(c.cosine) : -1.0;
        if (sc > score || (sc == score && c.e < pick->e)) {
          score = sc;
          pick = &c;
        }
      }
      dist[p] = pick->dist;
      element[p] = pick->e;
      xi[2 * p] = pick->xi[0];
      xi[2 * p + 1] = pick->xi[1];
      cosine[p] = pick->cosine;
    });
  }
  guard.rethrow();
}

}  // namespace bemcontact
