// Gauss-Legendre rules and the rules built from them.
#pragma once

#include <cmath>
#include <vector>

namespace bemcontact {

constexpr int kMaxGaussOrder = 64;

struct Rule1D {
  std::vector<double> x;  // nodes on [0, 1]
  std::vector<double> w;  // weights, sum 1
};

// n-point Gauss-Legendre rule on [0, 1] (Newton iteration on P_n).
inline Rule1D make_gauss_legendre(int n) {
  Rule1D r;
  r.x.resize(n);
  r.w.resize(n);
  for (int i = 0; i < (n + 1) / 2; ++i) {
    double z = std::cos(M_PI * (i + 0.75) / (n + 0.5));
    double dp = 0.0;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1.0, p1 = z;
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2.0 * k - 1.0) * z * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      if (n == 1) {
        p1 = z;
        p0 = 1.0;
      }
      dp = n * (z * p1 - p0) / (z * z - 1.0);
      const double dz = p1 / dp;
      z -= dz;
      if (std::fabs(dz) < 1e-16) break;
    }
    {
      // recompute derivative at the converged root
      double p0 = 1.0, p1 = z;
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2.0 * k - 1.0) * z * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      dp = (n == 1) ? 1.0 : n * (z * p1 - p0) / (z * z - 1.0);
    }
    const double w = 2.0 / ((1.0 - z * z) * dp * dp);
    r.x[i] = 0.5 * (1.0 - z);
    r.x[n - 1 - i] = 0.5 * (1.0 + z);
    r.w[i] = r.w[n - 1 - i] = 0.5 * w;
  }
  if (n % 2 == 1) r.x[n / 2] = 0.5;
  return r;
}

// Rules 1..kMaxGaussOrder, built once.
inline const Rule1D& gauss_rule(int n) {
  static const std::vector<Rule1D> rules = [] {
    std::vector<Rule1D> v(kMaxGaussOrder + 1);
    for (int k = 1; k <= kMaxGaussOrder; ++k) v[k] = make_gauss_legendre(k);
    return v;
  }();
  if (n < 1) n = 1;
  if (n > kMaxGaussOrder) n = kMaxGaussOrder;
  return rules[n];
}

// A 2D rule on an element's reference domain: local points and weights
// (weights include the reference-domain measure, without surface Jacobian).
struct Rule2D {
  std::vector<double> xi, eta, w;
  void add(double a, double b, double wt) {
    xi.push_back(a);
    eta.push_back(b);
    w.push_back(wt);
  }
  size_t size() const { return w.size(); }
};

// Tensor Gauss rule on the parametric rectangle [u0,u1] x [v0,v1].
inline void append_rectangle_rule(Rule2D& r, int n, double u0, double u1, double v0,
                                  double v1) {
  const Rule1D& g = gauss_rule(n);
  const double du = u1 - u0, dv = v1 - v0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      r.add(u0 + du * g.x[i], v0 + dv * g.x[j], du * dv * g.w[i] * g.w[j]);
}

// Collapsed (Duffy) Gauss rule on the parametric triangle (A, B, C).  The
// collapsed vertex is A, so a 1/r singularity at A is cancelled by the
// Jacobian; used both for regular triangles and for polar-type singular
// integration around a collocation point placed at A.
inline void append_triangle_rule(Rule2D& r, int ns, int nt, const double* A,
                                 const double* B, const double* C) {
  const Rule1D& gs = gauss_rule(ns);
  const Rule1D& gt = gauss_rule(nt);
  const double e1[2] = {B[0] - A[0], B[1] - A[1]};
  const double e2[2] = {C[0] - B[0], C[1] - B[1]};
  const double det = std::fabs(e1[0] * e2[1] - e1[1] * e2[0]);
  for (int i = 0; i < ns; ++i) {
    const double s = gs.x[i];
    for (int j = 0; j < nt; ++j) {
      const double t = gt.x[j];
      r.add(A[0] + s * (e1[0] + t * e2[0]), A[1] + s * (e1[1] + t * e2[1]),
            det * s * gs.w[i] * gt.w[j]);
    }
  }
}

}  // namespace bemcontact
