// nanobind bindings of the compiled core (module bemcontact._core).
// Argument names equal the C++ names; validation happens in Python.
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>

#include <algorithm>
#include <cstring>

#include "python/bind_common.hpp"
#include "bem/element.hpp"
#include "bem/integration.hpp"
#include "bem/operators.hpp"
#include "bem/quadrature.hpp"

#ifdef _OPENMP
#include <omp.h>
#endif

namespace nb = nanobind;
using namespace bemcontact;
using namespace bemcontact::bind;

void bind_hmatrix(nb::module_& mod);  // hmatrix_bindings.cpp

using NpArray = nb::ndarray<nb::numpy, double>;

namespace {

NpArray owned(double* data, std::initializer_list<size_t> shape) {
  nb::capsule owner(data, [](void* p) noexcept { delete[] static_cast<double*>(p); });
  return NpArray(data, shape.size(), shape.begin(), owner);
}

// Lagrange coefficients (cf, as lagrange_coefficients) of the basis of element
// type t through the local nodes xi (9 x 2, the first nodes_per_element(t)
// used); returns the smallest relative pivot.
double local_basis(int t, const double* xi, double* cf) {
  double xf[kMaxNodes][2];
  for (int k = 0; k < nodes_per_element(t); ++k) {
    xf[k][0] = xi[2 * k];
    xf[k][1] = xi[2 * k + 1];
  }
  return lagrange_coefficients(t, xf, cf);
}

int default_threads() {
#ifdef _OPENMP
  return omp_get_max_threads();
#else
  return 1;
#endif
}

// The dense operators and single element integrals (bem/operators.hpp,
// bem/integration.hpp).
void bind_operators(nb::module_& mod) {
  mod.def(
      "assemble_influence",
      [](CDouble2 nodes, CInt32_1 etype, CInt64_2 conn, CInt64_2 fconn, CDouble3 fxi,
         CDouble2 points, double shear_modulus, double nu, const QuadratureParams& q,
         int threads, Double2 H, Double2 G) {
        const MeshView m = make_view(nodes, etype, conn, fconn, fxi);
        const int64_t n = static_cast<int64_t>(points.shape(0));
        const double* pts = points.data();
        double* h = H.data();
        double* g = G.data();
        nb::gil_scoped_release release;
        assemble_influence(m, pts, n, shear_modulus, nu, q, threads, h, g);
      },
      nb::arg("nodes"), nb::arg("etype"), nb::arg("conn"), nb::arg("fconn"), nb::arg("fxi"),
      nb::arg("points"), nb::arg("shear_modulus"), nb::arg("nu"), nb::arg("q"),
      nb::arg("threads"), nb::arg("H"), nb::arg("G"),
      "Fill H and G (3N x 3N, row-major) for collocation at `points` (N x 3).");

  mod.def(
      "assemble_system",
      [](CDouble2 nodes, CInt32_1 etype, CInt64_2 conn, CInt64_2 fconn, CDouble3 fxi,
         CDouble2 points, double shear_modulus, double nu, const QuadratureParams& q,
         CUInt8_1 known_u,
         CDouble2 W, CInt64_1 bcols, int threads,
         nb::ndarray<double, nb::ndim<2>, nb::f_contig, nb::device::cpu> A, Double2 BW,
         Double2 BC) {
        const MeshView m = make_view(nodes, etype, conn, fconn, fxi);
        const int64_t n = static_cast<int64_t>(points.shape(0));
        if (known_u.shape(0) != static_cast<size_t>(3 * n) || W.shape(0) != known_u.shape(0) ||
            A.shape(0) < known_u.shape(0) || A.shape(1) < known_u.shape(0) ||
            BW.shape(0) != known_u.shape(0) || BW.shape(1) != W.shape(1) ||
            BC.shape(0) != known_u.shape(0) || BC.shape(1) != bcols.shape(0))
          throw nb::value_error("assemble_system: inconsistent shapes");
        const double* pts = points.data();
        const uint8_t* ku = known_u.data();
        const double* w = W.data();
        const int64_t s = static_cast<int64_t>(W.shape(1));
        const int64_t* bc = bcols.data();
        const int64_t nbc = static_cast<int64_t>(bcols.shape(0));
        double* a = A.data();
        const int64_t lda = static_cast<int64_t>(A.shape(0));
        double* bw = BW.data();
        double* bcp = BC.data();
        nb::gil_scoped_release release;
        assemble_system(m, pts, n, shear_modulus, nu, q, ku, w, s, bc, nbc, threads, a, lda, bw,
                        bcp);
      },
      nb::arg("nodes"), nb::arg("etype"), nb::arg("conn"), nb::arg("fconn"), nb::arg("fxi"),
      nb::arg("points"), nb::arg("shear_modulus"), nb::arg("nu"), nb::arg("q"),
      nb::arg("known_u"), nb::arg("W"), nb::arg("bcols"), nb::arg("threads"), nb::arg("A"),
      nb::arg("BW"), nb::arg("BC"),
      "Mixed system matrix A (column-major, top-left 3N x 3N block of the given array), "
      "B W and the columns bcols of B, without storing H and G.");

  mod.def(
      "element_influence",
      [](CDouble2 nodes, CInt32_1 etype, CInt64_2 conn, CInt64_2 fconn, CDouble3 fxi,
         int64_t element, CDouble2 x, int local, double shear_modulus, double nu,
         const QuadratureParams& q) {
        const MeshView m = make_view(nodes, etype, conn, fconn, fxi);
        const std::vector<Element> els = prepare_elements(m, std::min(q.max_order, kMaxCachedOrder), 1);
        const Element& e = els.at(static_cast<size_t>(element));
        const Kelvin K(shear_modulus, nu);
        const size_t ld = 3 * e.n;
        double* He = new double[3 * ld]();
        double* Ge = new double[3 * ld]();
        element_influence(e, x.data(), local, K, q, true, true, He, Ge);
        return nb::make_tuple(owned(He, {3, ld}), owned(Ge, {3, ld}));
      },
      nb::arg("nodes"), nb::arg("etype"), nb::arg("conn"), nb::arg("fconn"), nb::arg("fxi"),
      nb::arg("element"), nb::arg("x"), nb::arg("local"), nb::arg("shear_modulus"),
      nb::arg("nu"), nb::arg("q"),
      "Influence (H_e, G_e), each 3 x 3n, of one element on the point x (1 x 3).");
}

// Surface geometry and quadrature points of the elements (bem/element.hpp).
void bind_geometry(nb::module_& mod) {
  mod.def(
      "map_points",
      [](CDouble2 nodes, CInt32_1 etype, CInt64_2 conn, CInt64_1 elements, CDouble2 xi) {
        const size_t n = elements.shape(0);
        double* X = new double[3 * n];
        double* Nn = new double[3 * n];
        double* J = new double[n];
        for (size_t p = 0; p < n; ++p) {
          const int64_t e = elements.data()[p];
          const int t = etype.data()[e];
          double Xe[kMaxNodes][3];
          for (int k = 0; k < nodes_per_element(t); ++k) {
            const int64_t g = conn.data()[e * kMaxNodes + k];
            for (int d = 0; d < 3; ++d) Xe[k][d] = nodes.data()[3 * g + d];
          }
          const SurfacePoint sp = map_point(t, Xe, xi.data()[2 * p], xi.data()[2 * p + 1]);
          for (int d = 0; d < 3; ++d) {
            X[3 * p + d] = sp.x[d];
            Nn[3 * p + d] = sp.n[d];
          }
          J[p] = sp.jac;
        }
        return nb::make_tuple(owned(X, {n, 3}), owned(Nn, {n, 3}), owned(J, {n}));
      },
      nb::arg("nodes"), nb::arg("etype"), nb::arg("conn"), nb::arg("elements"), nb::arg("xi"),
      "Positions, unit normals and surface Jacobians at local points xi (P x 2) of elements (P,).");

  mod.def(
      "surface_quadrature",
      [](CDouble2 nodes, CInt32_1 etype, CInt64_2 conn, CInt64_2 fconn, CDouble3 fxi,
         int order) {
        const MeshView m = make_view(nodes, etype, conn, fconn, fxi);
        const size_t ne = static_cast<size_t>(m.n_elements);
        const size_t nq = static_cast<size_t>(order) * order;
        double* X = new double[ne * nq * 3];
        double* Nn = new double[ne * nq * 3];
        double* W = new double[ne * nq];
        double* Phi = new double[ne * nq * kMaxNodes]();
        for (size_t ie = 0; ie < ne; ++ie) {
          const int t = m.etype[ie];
          const int n = nodes_per_element(t);
          double Xe[kMaxNodes][3], cf[kMaxNodes * kMaxNodes];
          for (int k = 0; k < n; ++k) {
            const int64_t g = m.conn[ie * kMaxNodes + k];
            for (int d = 0; d < 3; ++d) Xe[k][d] = m.nodes[3 * g + d];
          }
          local_basis(t, m.fxi + ie * kMaxNodes * 2, cf);
          Rule2D r;
          if (is_triangle(t)) {
            const double A[2] = {0, 0}, B[2] = {1, 0}, C[2] = {0, 1};
            append_triangle_rule(r, order, order, A, B, C);
          } else {
            append_rectangle_rule(r, order, -1, 1, -1, 1);
          }
          for (size_t p = 0; p < nq; ++p) {
            const SurfacePoint sp = map_point(t, Xe, r.xi[p], r.eta[p]);
            const size_t o = ie * nq + p;
            for (int d = 0; d < 3; ++d) {
              X[3 * o + d] = sp.x[d];
              Nn[3 * o + d] = sp.n[d];
            }
            W[o] = r.w[p] * sp.jac;
            eval_basis(t, cf, r.xi[p], r.eta[p], Phi + kMaxNodes * o, nullptr, nullptr);
          }
        }
        return nb::make_tuple(owned(X, {ne, nq, 3}), owned(Nn, {ne, nq, 3}),
                              owned(W, {ne, nq}), owned(Phi, {ne, nq, (size_t)kMaxNodes}));
      },
      nb::arg("nodes"), nb::arg("etype"), nb::arg("conn"), nb::arg("fconn"), nb::arg("fxi"),
      nb::arg("order"),
      "Gauss points (E x Q x 3), normals, weights*Jacobian (E x Q) and functional basis "
      "values (E x Q x 9) with order x order points per element.");
}

// Functional (Lagrange) bases through given local nodes (bem/element.hpp).
void bind_bases(nb::module_& mod) {
  mod.def(
      "eval_basis",
      [](CInt32_1 etype, CDouble3 nodes_xi, CDouble2 xi) {
        // Lagrange basis through the given local nodes (one node set per point).
        const size_t np = etype.shape(0);
        double* N = new double[np * kMaxNodes]();
        double* Nx = new double[np * kMaxNodes]();
        double* Ny = new double[np * kMaxNodes]();
        for (size_t p = 0; p < np; ++p) {
          const int t = etype.data()[p];
          double cf[kMaxNodes * kMaxNodes];
          local_basis(t, nodes_xi.data() + p * kMaxNodes * 2, cf);
          eval_basis(t, cf, xi.data()[2 * p], xi.data()[2 * p + 1], N + kMaxNodes * p,
                     Nx + kMaxNodes * p, Ny + kMaxNodes * p);
        }
        return nb::make_tuple(owned(N, {np, (size_t)kMaxNodes}),
                              owned(Nx, {np, (size_t)kMaxNodes}),
                              owned(Ny, {np, (size_t)kMaxNodes}));
      },
      nb::arg("etype"), nb::arg("nodes_xi"), nb::arg("xi"),
      "Values and local derivatives (P x 9 each, zero padded) of the Lagrange basis of element "
      "type etype[p] through the local nodes nodes_xi[p] (P x 9 x 2) at the local point xi[p].");

  mod.def(
      "basis_conditioning",
      [](CInt32_1 etype, CDouble3 fxi) {
        const size_t ne = etype.shape(0);
        double* out = new double[ne];
        for (size_t ie = 0; ie < ne; ++ie) {
          const int t = etype.data()[ie];
          double cf[kMaxNodes * kMaxNodes];
          out[ie] = local_basis(t, fxi.data() + ie * kMaxNodes * 2, cf);
        }
        return owned(out, {ne});
      },
      nb::arg("etype"), nb::arg("fxi"),
      "Smallest relative pivot of each element's functional Vandermonde matrix (0: not unisolvent).");
}

}  // namespace

NB_MODULE(_core, mod) {
  mod.doc() = "bemcontact compiled core: element bases, quadrature, BEM operators";

  nb::class_<QuadratureParams>(mod, "QuadratureParams")
      .def(nb::init<>())
      .def_rw("tolerance", &QuadratureParams::tolerance)
      .def_rw("min_order", &QuadratureParams::min_order)
      .def_rw("max_order", &QuadratureParams::max_order)
      .def_rw("singular_order", &QuadratureParams::singular_order)
      .def_rw("max_angle", &QuadratureParams::max_angle)
      .def_rw("max_depth", &QuadratureParams::max_depth);

  bind_hmatrix(mod);

  mod.def("max_threads", &default_threads, "OpenMP threads available (1 without OpenMP).");

  bind_operators(mod);
  bind_geometry(mod);
  bind_bases(mod);
}
