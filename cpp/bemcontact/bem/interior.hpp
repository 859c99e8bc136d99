// Fields inside a body from its boundary solution (Somigliana's identity):
// the compiled evaluation behind bemcontact.bem.interior, whose docstring
// gives the identities, the Gauss order rule and the quadtree.  Elements are
// given in monomial form, position(xi) = sum_a monomial_a(xi) geo[e][a] and
// fields(xi) = sum_a monomial_a(xi) coef[e][a] (u then t), monomials in the
// order of element.hpp.  Points run in parallel (OpenMP); per point every
// element is integrated with a Gauss rule chosen from its distance, the near
// ones on pieces of a quadtree in local coordinates.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <vector>

#include "bem/quadrature.hpp"

namespace bemcontact {

// The largest Gauss order per direction an evaluator accepts (stack buffers).
constexpr int kMaxInteriorOrder = 16;

class InteriorEvaluator {
 public:
  // type: element type code (element.hpp); geo (m x k x 3) and coef (m x k x
  // 6) as above, copied; tolerance: relative accuracy asked of each element
  // integral; max_order: the largest order per direction before a piece is
  // cut in four; max_level: the deepest quadtree level.
  InteriorEvaluator(int type, int64_t n_elements, const double* geo, const double* coef,
                    double shear_modulus, double nu, double tolerance, int max_order,
                    int max_level);

  int64_t n_elements() const { return m_; }
  // Diameter of each element (the largest distance between its samples).
  const std::vector<double>& sizes() const { return size_; }

  // Per point x (n x 3): the distance to the surface, the element holding the
  // nearest surface point y and its local coordinates (n x 2), and the cosine
  // of x - y with the outward normal there (> 0: x lies outside).
  void nearest(const double* X, int64_t n, int threads, double* dist, int64_t* element,
               double* xi, double* cosine) const;

  // Stress (n x 6: xx, yy, zz, xy, yz, xz) or displacement (n x 3) at the
  // points X, the boundary displacement at (element[p], xi[p]) (the nearest
  // surface point) subtracted from u before integrating.
  void integrate(const double* X, const int64_t* element, const double* xi, int64_t n,
                 bool stresses, int threads, double* out) const;

 private:
  struct Piece {  // an affine image c + B xi_ref of the reference cell
    double c[2];
    double B[4];  // row-major 2 x 2
  };
  struct Candidate {  // a surface point nearest to x on one element
    int64_t e;
    double xi[2], dist, cosine;
  };
  Candidate project(int64_t e, const double* x) const;
  void map(int64_t e, double xi, double eta, double* y, double* nJ, double* F) const;
  int order(double d, double size) const;
  const double* element_rule(int64_t e, int k, double* scratch) const;
  void fill(int64_t e, const Piece& p, const Rule2D& r, double* block) const;
  template <bool kStress>
  void batch(const double* X, const int64_t* element, const double* xi, int nb,
             double* out) const;
  template <bool kStress>
  void quadtree(const double* x, const double* u0, int64_t e, const Piece& p, int level,
                double* acc, double* scratch) const;

  int type_, k_, n_samples_;
  int64_t m_;
  bool triangle_;
  std::vector<double> geo_, coef_;
  double G_, nu_;
  int max_order_, max_level_;
  // beta_[k]: order <= k  <=>  beta = 2 d / size >= beta_[k]
  std::array<double, kMaxInteriorOrder + 1> beta_{};
  std::array<Rule2D, kMaxInteriorOrder + 1> ref_;  // reference rules
  double samples_[9][2];
  std::vector<double> sample_y_;  // m x n_samples x 3
  std::vector<double> size_;      // m
  std::vector<double> far_;       // per element: centre (3), radius, then (r + beta_k size / 2)^2
  int far_stride_;
  // The whole-element rule of order k: per element a block of kFields rows of
  // k^2 points, each filled when a point first needs it (the high orders only
  // near the points).  state: 0 empty, 1 being filled, 2 filled.
  struct RuleCache {
    std::once_flag once;
    std::unique_ptr<double[]> blocks;
    std::unique_ptr<std::atomic<uint8_t>[]> state;
  };
  mutable std::array<RuleCache, kMaxInteriorOrder + 1> rules_;
};

}  // namespace bemcontact
