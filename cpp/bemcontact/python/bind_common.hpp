// Shared by the nanobind binding files: array types and the MeshView of the
// arrays Python passes (Discretization.core_arrays()).
#pragma once

#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>

#include "bem/integration.hpp"

namespace bemcontact::bind {

namespace nb = nanobind;

using CDouble2 = nb::ndarray<const double, nb::ndim<2>, nb::c_contig, nb::device::cpu>;
using CDouble3 = nb::ndarray<const double, nb::ndim<3>, nb::c_contig, nb::device::cpu>;
using CInt64_2 = nb::ndarray<const int64_t, nb::ndim<2>, nb::c_contig, nb::device::cpu>;
using CInt64_1 = nb::ndarray<const int64_t, nb::ndim<1>, nb::c_contig, nb::device::cpu>;
using CInt32_1 = nb::ndarray<const int32_t, nb::ndim<1>, nb::c_contig, nb::device::cpu>;
using CUInt8_1 = nb::ndarray<const uint8_t, nb::ndim<1>, nb::c_contig, nb::device::cpu>;
using Double2 = nb::ndarray<double, nb::ndim<2>, nb::c_contig, nb::device::cpu>;

inline MeshView make_view(CDouble2 nodes, CInt32_1 etype, CInt64_2 conn, CInt64_2 fconn,
                          CDouble3 fxi) {
  MeshView m;
  m.nodes = nodes.data();
  m.n_nodes = static_cast<int64_t>(nodes.shape(0));
  m.etype = etype.data();
  m.conn = conn.data();
  m.fconn = fconn.data();
  m.fxi = fxi.data();
  m.n_elements = static_cast<int64_t>(etype.shape(0));
  return m;
}

}  // namespace bemcontact::bind
