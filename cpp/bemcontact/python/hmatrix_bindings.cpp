// nanobind bindings of the H-matrix (part of module bemcontact._core).
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/vector.h>

#include <cstring>

#include "python/bind_common.hpp"
#include "hmat/hlu.hpp"
#include "hmat/hmatrix.hpp"
#include "la/lapack.hpp"

namespace nb = nanobind;
using namespace bemcontact;
using namespace bemcontact::bind;

namespace {

using NpArray = nb::ndarray<nb::numpy, double>;
using NpInt = nb::ndarray<nb::numpy, int64_t>;

template <class T>
nb::ndarray<nb::numpy, T> owned_copy(const T* src, std::initializer_list<size_t> shape) {
  size_t n = 1;
  for (size_t s : shape) n *= s;
  T* data = new T[n > 0 ? n : 1];
  if (n) std::memcpy(data, src, n * sizeof(T));
  nb::capsule owner(data, [](void* p) noexcept { delete[] static_cast<T*>(p); });
  return nb::ndarray<nb::numpy, T>(data, shape.size(), shape.begin(), owner);
}

}  // namespace

void* capsule_pointer(nb::handle cap) {
  PyObject* o = cap.ptr();
  if (!PyCapsule_CheckExact(o)) throw nb::type_error("expected a capsule");
  void* p = PyCapsule_GetPointer(o, PyCapsule_GetName(o));
  if (!p) throw nb::python_error();
  return p;
}

// f := the routine of a scipy.linalg.cython_lapack / cython_blas capsule
template <class F>
void set_routine(F*& f, nb::handle cap) {
  f = reinterpret_cast<F*>(capsule_pointer(cap));
}

namespace {

// The LAPACK and BLAS tables (la/lapack.hpp) from SciPy's capsules.
void bind_lapack(nb::module_& mod) {
  nb::class_<Lapack>(mod, "Lapack")
      .def(
          "__init__",
          [](Lapack* self, nb::handle dgeqrf, nb::handle dormqr, nb::handle dgesvd,
             nb::handle dgesdd) {
            new (self) Lapack();
            set_routine(self->dgeqrf, dgeqrf);
            set_routine(self->dormqr, dormqr);
            set_routine(self->dgesvd, dgesvd);
            if (!dgesdd.is_none()) set_routine(self->dgesdd, dgesdd);
          },
          nb::arg("dgeqrf"), nb::arg("dormqr"), nb::arg("dgesvd"), nb::arg("dgesdd").none() = nb::none(),
          "LAPACK routines from scipy.linalg.cython_lapack.__pyx_capi__ capsules.");

  nb::class_<Blas>(mod, "Blas")
      .def(
          "__init__",
          [](Blas* self, nb::handle dgemm, nb::handle dtrsm, nb::handle dgetrf,
             nb::handle dlaswp) {
            new (self) Blas();
            set_routine(self->dgemm, dgemm);
            set_routine(self->dtrsm, dtrsm);
            set_routine(self->dgetrf, dgetrf);
            set_routine(self->dlaswp, dlaswp);
          },
          nb::arg("dgemm"), nb::arg("dtrsm"), nb::arg("dgetrf"), nb::arg("dlaswp"),
          "BLAS (cython_blas) and LAPACK (cython_lapack) routines for the H-LU.");
}

// HMatrix: the build, its statistics and the product.
void def_hmatrix_build(nb::class_<HMatrix>& cls) {
  cls
      .def(
          "__init__",
          [](HMatrix* self, CDouble2 nodes, CInt32_1 etype, CInt64_2 conn, CInt64_2 fconn,
             CDouble3 fxi, CDouble2 points, double shear_modulus, double nu,
             const QuadratureParams& q, const HParams& hp, CUInt8_1 known_u, CDouble2 W,
             const Lapack& lapack, int threads) {
            const MeshView m = make_view(nodes, etype, conn, fconn, fxi);
            const double* pts = points.data();
            const int64_t n = static_cast<int64_t>(points.shape(0));
            if (known_u.shape(0) != static_cast<size_t>(3 * n) ||
                W.shape(0) != static_cast<size_t>(3 * n))
              throw nb::value_error("known_u and W must have 3N rows");
            const uint8_t* ku = known_u.data();
            const double* w = W.data();
            const int64_t s = static_cast<int64_t>(W.shape(1));
            nb::gil_scoped_release release;
            new (self) HMatrix(m, pts, n, shear_modulus, nu, q, hp, ku, w, s, lapack, threads);
          },
          nb::arg("nodes"), nb::arg("etype"), nb::arg("conn"), nb::arg("fconn"), nb::arg("fxi"),
          nb::arg("points"), nb::arg("shear_modulus"), nb::arg("nu"), nb::arg("q"),
          nb::arg("hp"), nb::arg("known_u"), nb::arg("W"), nb::arg("lapack"), nb::arg("threads"))
      .def_prop_ro("n_points", &HMatrix::n_points)
      .def_prop_ro("stored_bytes", &HMatrix::stored_bytes)
      .def("rms_h", &HMatrix::rms_h, "root-mean-square entry of H (global truncation; else 0)")
      .def("rms_g", &HMatrix::rms_g, "root-mean-square entry of G (global truncation; else 0)")
      .def_prop_ro("build_seconds", &HMatrix::build_seconds)
      .def_prop_ro("dense_seconds", &HMatrix::dense_seconds)
      .def_prop_ro("aca_seconds", &HMatrix::aca_seconds)
      .def_prop_ro("row_integrals", &HMatrix::row_integrals)
      .def_prop_ro("col_integrals", &HMatrix::col_integrals)
      .def("bw",
           [](const HMatrix& h) {
             return owned_copy(h.bw().data(),
                               {static_cast<size_t>(3 * h.n_points()),
                                static_cast<size_t>(h.bw_columns())});
           },
           "B W computed during the build (3N x s).")
      .def(
          "apply",
          [](const HMatrix& h, CDouble2 x, Double2 y, int threads) {
            const int64_t k = static_cast<int64_t>(x.shape(1));
            const double* px = x.data();
            double* py = y.data();
            nb::gil_scoped_release release;
            h.apply(px, py, k, threads);
          },
          nb::arg("x"), nb::arg("y"), nb::arg("threads"),
          "y = A x (3N x k each, row-major, original dof order).");
}

// HMatrix: exact entries and G columns, the blocks and the permutation.
void def_hmatrix_inspection(nb::class_<HMatrix>& cls) {
  cls
      .def(
          "entries",
          [](const HMatrix& h, CInt64_1 rows, CInt64_1 cols) {
            const size_t nr = rows.shape(0), nc = cols.shape(0);
            std::vector<double> H(nr * nc), G(nr * nc);
            h.entries(rows.data(), nr, cols.data(), nc, H.data(), G.data());
            return nb::make_tuple(owned_copy(H.data(), {nr, nc}), owned_copy(G.data(), {nr, nc}));
          },
          nb::arg("rows"), nb::arg("cols"),
          "Exact entries H[rows][:, cols], G[rows][:, cols] from the element integrals.")
      .def("block_info",
           [](const HMatrix& h) {
             // per block: tau begin, tau size, sigma begin, sigma size, rank (-1 dense),
             // ACA rank before recompression, failed checks
             const auto& B = h.blocks();
             const auto& C = h.clusters();
             std::vector<int64_t> out(7 * B.size());
             for (size_t i = 0; i < B.size(); ++i) {
               out[7 * i] = C[B[i].tau].begin;
               out[7 * i + 1] = C[B[i].tau].size();
               out[7 * i + 2] = C[B[i].sigma].begin;
               out[7 * i + 3] = C[B[i].sigma].size();
               out[7 * i + 4] = B[i].rank;
               out[7 * i + 5] = B[i].aca_rank;
               out[7 * i + 6] = B[i].aca_checks_failed;
             }
             return owned_copy(out.data(), {B.size(), (size_t)7});
           })
      .def(
          "block_matrix",
          [](const HMatrix& h, int64_t i) {
            // block i of A as dense, rows and columns in cluster order
            const HBlock& b = h.blocks().at(static_cast<size_t>(i));
            const auto& C = h.clusters();
            const size_t m = 3 * C[b.tau].size(), n = 3 * C[b.sigma].size();
            if (b.rank < 0) return owned_copy(b.A.data(), {m, n});
            std::vector<double> A(m * n, 0.0), U, V;
            b.factors(U, V, m, n);
            for (int l = 0; l < b.rank; ++l)
              for (size_t r = 0; r < m; ++r) {
                const double u = U[l * m + r];
                for (size_t c = 0; c < n; ++c) A[r * n + c] += u * V[l * n + c];
              }
            return owned_copy(A.data(), {m, n});
          },
          nb::arg("i"), "Block i of A expanded to dense (rows tau, columns sigma, cluster order).")
      .def("perm",
           [](const HMatrix& h) { return owned_copy(h.perm().data(), {h.perm().size()}); })
      .def(
          "g_columns",
          [](const HMatrix& h, CInt64_1 cols, int threads) {
            const size_t nc = cols.shape(0), n3 = 3 * static_cast<size_t>(h.n_points());
            for (size_t b = 0; b < nc; ++b)
              if (cols.data()[b] < 0 || static_cast<size_t>(cols.data()[b]) >= n3)
                throw nb::index_error("g_columns: dof index out of range");
            double* data = new double[n3 * nc > 0 ? n3 * nc : 1];
            nb::capsule owner(data, [](void* p) noexcept { delete[] static_cast<double*>(p); });
            {
              nb::gil_scoped_release release;
              h.g_columns(cols.data(), static_cast<int64_t>(nc), data, threads);
            }
            size_t shape[2] = {n3, nc};
            return NpArray(data, 2, shape, owner);
          },
          nb::arg("cols"), nb::arg("threads"),
          "Columns cols of G over all rows (3N x nc), from the element integrals.")
      .def(
          "diagonal_blocks",
          [](const HMatrix& h) {
            // dense diagonal leaves of A: list of (original nodes, A block)
            nb::list out;
            const auto& C = h.clusters();
            for (const HBlock& b : h.blocks()) {
              if (b.tau != b.sigma || b.rank >= 0) continue;
              const HCluster& c = C[b.tau];
              const size_t s = c.size();
              out.append(nb::make_tuple(owned_copy(h.perm().data() + c.begin, {s}),
                                        owned_copy(b.A.data(), {3 * s, 3 * s})));
            }
            return out;
          },
          "The dense diagonal leaf blocks of A: [(nodes (s,), A (3s x 3s))].");
}

void bind_hlu(nb::module_& mod) {
  nb::class_<HLU>(mod, "HLU")
      .def(
          "__init__",
          [](HLU* self, const HMatrix& h, const Lapack& lapack, const Blas& blas, double eps,
             CDouble2 U, CDouble2 V, int threads) {
            const size_t n3 = 3 * static_cast<size_t>(h.n_points());
            if (U.shape(0) != n3 || V.shape(0) != n3 || U.shape(1) != V.shape(1))
              throw nb::value_error("HLU: U and V must both be 3N x r");
            const double* pu = U.data();
            const double* pv = V.data();
            const int64_t r = static_cast<int64_t>(U.shape(1));
            nb::gil_scoped_release release;
            new (self) HLU(h, lapack, blas, eps, pu, pv, r, threads);
          },
          nb::arg("hmatrix"), nb::arg("lapack"), nb::arg("blas"), nb::arg("eps"), nb::arg("U"),
          nb::arg("V"), nb::arg("threads") = 1,
          "H-LU factorization of the H-matrix's A + U V^T, low-rank sums truncated to eps.")
      .def(
          "solve",
          [](const HLU& f, Double2 b) {
            if (b.shape(0) != static_cast<size_t>(f.n_dofs()))
              throw nb::value_error("solve: b must have 3N rows");
            double* pb = b.data();
            const int64_t k = static_cast<int64_t>(b.shape(1));
            nb::gil_scoped_release release;
            f.solve(pb, k);
          },
          nb::arg("b"), "Solve A X = B in place (B: 3N x k, row-major, original dof order).")
      .def_prop_ro("stored_doubles", &HLU::stored_doubles)
      .def_prop_ro("factor_seconds", &HLU::factor_seconds)
      .def_prop_ro("max_rank", &HLU::max_rank);
}

}  // namespace

void bind_hmatrix(nb::module_& mod) {
  nb::class_<HParams>(mod, "HParams")
      .def(nb::init<>())
      .def_rw("eps", &HParams::eps)
      .def_rw("eta", &HParams::eta)
      .def_rw("leaf_size", &HParams::leaf_size)
      .def_rw("max_rank", &HParams::max_rank)
      .def_rw("checks", &HParams::checks)
      .def_rw("global_", &HParams::global)
      .def_rw("mixed", &HParams::mixed)
      .def_rw("norm_samples", &HParams::norm_samples);

  bind_lapack(mod);

  nb::class_<HMatrix> cls(mod, "HMatrix");
  def_hmatrix_build(cls);
  def_hmatrix_inspection(cls);

  bind_hlu(mod);
}
