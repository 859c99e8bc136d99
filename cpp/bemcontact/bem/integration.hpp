// Element integration for collocation BEM with the Kelvin fundamental
// solution: the influence (blocks of H and G) of one element on one
// collocation point, by a regular Gauss rule of an order chosen from the
// distance, by adaptive subdivision (nearly singular) or by a polar rule
// around the point (singular).  The elements of a mesh are prepared once.
#pragma once

#include <cstdint>
#include <vector>

#include "bem/element.hpp"
#include "bem/kernels.hpp"
#include "bem/quadrature.hpp"

namespace bemcontact {

// A validated surface discretization, as plain arrays (owned by Python).
struct MeshView {
  const double* nodes = nullptr;   // (n_nodes, 3)
  const int32_t* etype = nullptr;  // (n_elements,)
  const int64_t* conn = nullptr;   // (n_elements, 9) geometric nodes, -1 padded
  const int64_t* fconn = nullptr;  // (n_elements, 9) functional nodes, -1 padded
  const double* fxi = nullptr;     // (n_elements, 9, 2) local coords of functional nodes
  int64_t n_nodes = 0;
  int64_t n_elements = 0;
};

// Regular rules of orders 1..kMaxCachedOrder are precomputed per element
// (points, normals, weights x Jacobian, basis values); higher orders are
// evaluated on the fly.
constexpr int kMaxCachedOrder = 4;

struct QuadratureParams {
  double tolerance = 1e-8;   // target relative error of each regular integral
  int min_order = 2;         // Gauss points per direction, regular rule
  int max_order = 10;        // above this, the element is subdivided instead
  int singular_order = 12;   // radial and angular order of the polar rule
  double max_angle = 0.7854; // polar rule: largest angle of one sub-triangle (rad)
  int max_depth = 14;        // subdivision depth limit (nearly singular)
};

// One element, prepared for integration.
struct Element {
  int type = 0, n = 0;
  double X[kMaxNodes][3];
  int64_t f[kMaxNodes];
  double fxi[kMaxNodes][2];
  double cf[kMaxNodes * kMaxNodes];  // functional Lagrange coefficients
  double gm[kMaxNodes][3];  // geometry in monomial form: x = sum_m mono_m(xi, eta) gm[m]
  double centroid[3], radius, diam;
  // cached regular rules: per order o (index o), the mapped points as
  // structure of arrays (x, y, z, nx, ny, nz, wJ; then phi, np x n).
  std::vector<std::vector<double>> cache;
};

std::vector<Element> prepare_elements(const MeshView& m, int max_cached_order, int threads);

// Influence of element e on collocation point x (3 x 3n blocks, row-major,
// column 3k + j for functional node k, component j).  If `local` >= 0 the
// point is functional node `local` of the element (singular integration; the
// H column of that node is left zero).
void element_influence(const Element& e, const double* x, int local, const Kelvin& K,
                       const QuadratureParams& q, bool want_h, bool want_g, double* He,
                       double* Ge);

}  // namespace bemcontact
