"""Dump one linear-field cube (bemcontact.bench.linear_field_cube) for the
hmat-oss comparison: mesh arrays, collocation points, known_u, material and
quadrature settings, the diagonal 3x3 blocks of A, a random x_true and the
reference product b = A x_true.

Reference A: the dense mixed system (operators.assemble_system, exact
rigid-body rows) when ``--reference dense``; the project's CompressedSystem at
eps 1e-10 (storage double) when ``--reference h1e-10`` (the 10k case).

    python export_case.py --nodes 2000 --out /tmp/hmatoss/N2000 [--reference dense|h1e-10]

Files (raw little-endian, C order): nodes.f64 (n_nodes,3), etype.i32 (ne,),
conn.i64 (ne,9), fconn.i64 (ne,9), fxi.f64 (ne,9,2), points.f64 (N,3),
known_u.u8 (3N,), adiag.f64 (N,3,3) = A[3i+r, 3i+c], x_true.f64 (3N,),
b_ref.f64 (3N,), and the physical case of bench one-body: b_phys.f64 = B values
(the right-hand side of the linear-field cube), x_phys.f64 = its exact
unknowns (traction at displacement-given dofs, displacement elsewhere);
meta.json.
"""

from __future__ import annotations

import argparse
import json
import pathlib
import time

import numpy as np

from bemcontact.bench import linear_field_cube
from bemcontact.hmatrix import CompressedSystem, HMatrixOptions
from bemcontact.operators import QuadratureOptions, assemble_system


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--nodes", type=int, required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--reference", choices=("dense", "h1e-10"), default="dense")
    ap.add_argument("--threads", type=int, default=2)
    a = ap.parse_args()
    out = pathlib.Path(a.out)
    out.mkdir(parents=True, exist_ok=True)

    body, grad, sigma = linear_field_cube(a.nodes)
    d = body.discretization
    ku, values = body.boundary_data(body.boundary_conditions)
    ku = np.asarray(ku, dtype=bool)
    values = np.asarray(values, dtype=float).reshape(-1)
    # the exact unknowns of the linear field: traction where the displacement
    # is given, displacement where the traction is given
    u_ex = (d.points @ grad.T).reshape(-1)
    t_ex = (d.normals @ sigma).reshape(-1)
    x_phys = np.where(ku, t_ex, u_ex)
    m = body.material
    quad = body.quadrature or QuadratureOptions()
    nodes, etype, conn, fconn, fxi = d.core_arrays()
    N = d.n_points
    n = 3 * N
    rng = np.random.default_rng(0)
    x_true = rng.standard_normal(n)

    t0 = time.perf_counter()
    if a.reference == "dense":
        A, BW, _ = assemble_system(d, m.shear_modulus, m.poisson_ratio, ku, W=values,
                                   quadrature=quad, threads=a.threads)
        b_phys = BW[:, 0]
        b_ref = A @ x_true
        adiag = np.empty((N, 3, 3))
        for r in range(3):
            for c in range(3):
                adiag[:, r, c] = A[3 * np.arange(N) + r, 3 * np.arange(N) + c]
        del A
    else:
        cs = CompressedSystem(d, m.shear_modulus, m.poisson_ratio, ku, values, quad,
                              HMatrixOptions(eps=1e-10, storage="double"), a.threads)
        b_phys = cs.BW
        b_ref = cs.matvec(x_true)
        adiag = np.empty((N, 3, 3))
        batch = 200
        for s in range(0, N, batch):
            idx = np.arange(s, min(N, s + batch))
            dofs = (3 * idx[:, None] + np.arange(3)).ravel()
            H, G = cs.entries(dofs, dofs)
            Ab = np.where(ku[dofs][None, :], -G, H)
            for t, i in enumerate(idx):
                adiag[i] = Ab[3 * t:3 * t + 3, 3 * t:3 * t + 3]
    ref_s = time.perf_counter() - t0

    def dump(name, arr, dtype):
        np.ascontiguousarray(arr, dtype=dtype).tofile(out / name)

    dump("nodes.f64", nodes, np.float64)
    dump("etype.i32", etype, np.int32)
    dump("conn.i64", conn, np.int64)
    dump("fconn.i64", fconn, np.int64)
    dump("fxi.f64", fxi, np.float64)
    dump("points.f64", d.points, np.float64)
    dump("known_u.u8", ku, np.uint8)
    dump("adiag.f64", adiag, np.float64)
    dump("x_true.f64", x_true, np.float64)
    dump("b_ref.f64", b_ref, np.float64)
    dump("x_phys.f64", x_phys, np.float64)
    dump("b_phys.f64", b_phys, np.float64)
    meta = {
        "requested_nodes": a.nodes, "n_points": int(N), "n_nodes": int(nodes.shape[0]),
        "n_elements": int(etype.shape[0]), "max_nodes": int(conn.shape[1]),
        "shear_modulus": float(m.shear_modulus), "poisson_ratio": float(m.poisson_ratio),
        "quadrature": {"tolerance": quad.tolerance, "min_order": quad.min_order,
                       "max_order": quad.max_order, "singular_order": quad.singular_order,
                       "max_angle": quad.max_angle, "max_depth": quad.max_depth},
        "reference": a.reference, "reference_seconds": ref_s,
        "known_u_fraction": float(ku.mean()),
        "u_scale": float(np.abs(u_ex).max()), "t_scale": float(np.abs(sigma).max()),
    }
    (out / "meta.json").write_text(json.dumps(meta, indent=1))
    print(json.dumps(meta))


if __name__ == "__main__":
    main()
