"""The project's own H-matrix (CompressedSystem + HFactor) on a case written
by export_case.py: build, memory, product error against the reference
b_ref = A x_true, H-LU, solve error.  One JSON line on stdout.

    python ours_bench.py CASE_DIR --eps 1e-7 --threads 1 [--storage double|mixed] [--leaf 48]
"""

from __future__ import annotations

import argparse
import json
import os
import pathlib
import resource
import time

import numpy as np
import threadpoolctl

from bemcontact.bench import linear_field_cube
from bemcontact.hmatrix import CompressedSystem, HMatrixOptions


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("case")
    ap.add_argument("--eps", type=float, default=1e-7)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--storage", default="double")
    ap.add_argument("--leaf", type=int, default=48)
    a = ap.parse_args()
    case = pathlib.Path(a.case)
    meta = json.loads((case / "meta.json").read_text())
    body, _, _ = linear_field_cube(meta["requested_nodes"])
    d = body.discretization
    N = d.n_points
    n = 3 * N
    pts = np.fromfile(case / "points.f64").reshape(N, 3)
    assert np.array_equal(pts, d.points), "case does not match the regenerated cube"
    ku = np.fromfile(case / "known_u.u8", dtype=np.uint8).astype(bool)
    x_true = np.fromfile(case / "x_true.f64")
    b_ref = np.fromfile(case / "b_ref.f64")
    m = body.material
    opt = HMatrixOptions(eps=a.eps, storage=a.storage, leaf_size=a.leaf)
    # BLAS to one thread everywhere (the H-LU does it itself; the build's
    # LAPACK calls run inside its OpenMP threads)
    with threadpoolctl.threadpool_limits(limits=1, user_api="blas"):
        t0, c0 = time.perf_counter(), time.process_time()
        cs = CompressedSystem(d, m.shear_modulus, m.poisson_ratio, ku, None, body.quadrature,
                              opt, a.threads)
        build_wall = time.perf_counter() - t0
        build_cpu = time.process_time() - c0
        st = cs.stats()
        t1 = time.perf_counter()
        y = cs.matvec(x_true)
        matvec_s = time.perf_counter() - t1
        mv_err = float(np.linalg.norm(y - b_ref) / np.linalg.norm(b_ref))
        bp = np.fromfile(case / "b_phys.f64")
        pm_err = float(np.linalg.norm(cs.matvec(np.fromfile(case / "x_phys.f64")) - bp)
                       / np.linalg.norm(bp))
        c1 = time.process_time()
        f = cs.factor()
        lu_cpu = time.process_time() - c1
        t2 = time.perf_counter()
        x = f.solve(b_ref)
        solve_s = time.perf_counter() - t2
        r = b_ref - cs.matvec(x)
        residual = float(np.linalg.norm(r) / np.linalg.norm(b_ref))
        x2 = x + f.solve(r)
        b_phys = np.fromfile(case / "b_phys.f64")
        xp = f.solve(b_phys)
        xp2 = xp + f.solve(b_phys - cs.matvec(xp))
    x_phys = np.fromfile(case / "x_phys.f64")

    def field_err(x):
        e = np.abs(x - x_phys)
        return float(max(e[ku].max() / meta["t_scale"], e[~ku].max() / meta["u_scale"]))

    phys_err, phys_refined = field_err(xp), field_err(xp2)
    sv_err = float(np.linalg.norm(x - x_true) / np.linalg.norm(x_true))
    refined = float(np.linalg.norm(x2 - x_true) / np.linalg.norm(x_true))
    out = {
        "code": "bemcontact", "storage": a.storage, "nodes": int(N), "unknowns": int(n),
        "eps": a.eps, "threads": a.threads, "leaf_dofs": 3 * a.leaf, "eta": opt.eta,
        "build_s": cs.build_seconds, "build_wall_s": build_wall, "build_cpu_s": build_cpu,
        "compressed_mb": cs.stored_bytes / 1e6, "dense_mb": cs.dense_bytes / 1e6,
        "blocks": st["blocks"], "low_rank_blocks": st["low_rank_blocks"],
        "max_rank": st["max_rank"], "mean_rank": st["mean_rank"],
        "integrals_build": int(cs._h.row_integrals + cs._h.col_integrals),
        "matvec_s": matvec_s, "matvec_rel_err": mv_err, "phys_matvec_err": pm_err,
        "lu_s": f.factor_seconds, "lu_cpu_s": lu_cpu, "lu_mb": f.stored_bytes / 1e6, "lu_max_rank": f.max_rank,
        "solve_s": solve_s, "solve_rel_err": sv_err, "residual": residual,
        "refined_rel_err": refined, "phys_err": phys_err, "phys_refined_err": phys_refined, "load1": os.getloadavg()[0],
        "peak_rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0,
        "reference": meta["reference"],
    }
    print(json.dumps(out))


if __name__ == "__main__":
    main()
