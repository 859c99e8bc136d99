"""One-body BEM benchmark: a unit cube (quad4) at about 500 to 5,000
collocation nodes under mixed boundary conditions with a known exact solution
(a linear displacement field: displacement prescribed on three faces,
traction on the other three), so each row also reports the error.

Prints a Markdown table: nodes, assembly s at 2 and at 1 thread (and the
speed-up), solve s (LAPACK getrf + getrs), peak RSS MB of the process, influence
coefficients (H and G entries) per second per core, the GFLOP/s of the
system's LU (LAPACK getrf on the assembled A, in place) and of the whole solve
(getrf, gecon, getrs) against scipy.linalg.lu_factor on a random matrix of the
same size in the same process ("LU ratio", "solve ratio"), and the max
relative error vs exact.

Each size runs in its own subprocess so the peak RSS is that size's.
Usage:  python benchmarks/bem_one_body_N500_5000.py [--sizes 8,12,16,20,26]
"""

from __future__ import annotations

import argparse
import json
import resource
import sys
import time


def one(divisions: int) -> dict:
    import numpy as np
    import scipy.linalg

    from bemcontact.bench import linear_field_cube

    body, A, sigma = linear_field_cube(divisions=divisions)

    def u(X):
        return X @ A.T

    d = body.discretization
    n = d.n_points
    # assembly alone at 1 thread (then discarded), to show the OpenMP speed-up
    t0 = time.perf_counter()
    H, G = body.assemble(threads=1)
    t_asm1 = time.perf_counter() - t0
    del H, G
    sol = body.solve(threads=2)
    t_asm2, t_solve, t_getrf = sol.timings["assembly"], sol.timings["solve"], sol.timings["factor"]
    exact_t = sol.normals @ sigma
    exact_u = u(sol.points)
    err = max(
        np.abs(sol.traction - exact_t).max() / np.abs(sigma).max(),
        np.abs(sol.displacement - exact_u).max() / np.abs(exact_u).max(),
    )
    del sol
    m = 3 * n
    flops = 2.0 / 3.0 * m**3 + 2.0 * m**2
    R = np.random.default_rng(0).standard_normal((m, m))
    t0 = time.perf_counter()
    scipy.linalg.lu_factor(R, overwrite_a=True, check_finite=False)
    t_ref = time.perf_counter() - t0
    coeffs = 2.0 * m * m
    return {
        "divisions": divisions,
        "nodes": n,
        "unknowns": m,
        "assembly_s_2t": t_asm2,
        "assembly_s_1t": t_asm1,
        "solve_s": t_solve,
        "peak_rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0,
        "coeffs_per_s_per_core": coeffs / t_asm2 / 2.0,
        "solve_gflops": flops / t_solve / 1e9,
        "getrf_gflops": (2.0 / 3.0 * m**3) / t_getrf / 1e9,
        "lu_factor_gflops": (2.0 / 3.0 * m**3) / t_ref / 1e9,
        "error": err,
    }


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--sizes", default="8,12,16,20,26", help="cube divisions per edge")
    p.add_argument("--one", type=int, help=argparse.SUPPRESS)
    a = p.parse_args()
    if a.one:
        print(json.dumps(one(a.one)))
        return
    from _common import machine_line, run_one

    rows = []
    for s in [int(x) for x in a.sizes.split(",")]:
        rows.append(run_one(__file__, s))
        print(f"  done: {s} divisions, {rows[-1]['nodes']} nodes", file=sys.stderr, flush=True)
    print(machine_line() + "\n")
    print(
        "| nodes | unknowns | assembly s (2 thr) | assembly s (1 thr) | speed-up | solve s "
        "| peak RSS MB | coeffs/s/core | solve GFLOP/s | LU GFLOP/s | lu_factor GFLOP/s "
        "| LU ratio | solve ratio | max rel. error |"
    )
    print("|---:" * 14 + "|")
    for r in rows:
        print(
            f"| {r['nodes']} | {r['unknowns']} | {r['assembly_s_2t']:.2f} | {r['assembly_s_1t']:.2f} "
            f"| {r['assembly_s_1t'] / r['assembly_s_2t']:.2f} | {r['solve_s']:.2f} "
            f"| {r['peak_rss_mb']:.0f} | {r['coeffs_per_s_per_core']:.3g} "
            f"| {r['solve_gflops']:.1f} | {r['getrf_gflops']:.1f} | {r['lu_factor_gflops']:.1f} "
            f"| {r['getrf_gflops'] / r['lu_factor_gflops']:.2f} "
            f"| {r['solve_gflops'] / r['lu_factor_gflops']:.2f} | {r['error']:.1e} |"
        )


if __name__ == "__main__":
    main()
