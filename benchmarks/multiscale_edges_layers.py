"""Where the half-space is wrong: a sphere near a block's edge and on a thin
layer, by the full path (the reference), by the grid with the bodies'
corrections, and by the grid on two half-spaces (the corrections off).

    python benchmarks/multiscale_edges_layers.py [--a-over-h 8] [--json FILE]

The benchmark's steel sphere (R = 10 mm), frictionless, pressed 0.03 mm
(a ≈ 0.55 mm) on a steel block 20 × 20 mm whose base is clamped: its apex
d = 10, 5, 3, 2 contact radii from the block's x = +10 edge (block 10 mm
thick), or centred on a block t = 10, 4, 2, 1 contact radii thick.  Full
path: both bodies meshed at h = a/(a/h) within 1.1a of the apex.  Grid: the
bodies meshed at 0.5 mm near the apex (at most half the layer's thickness),
cells of a/25.  Prints per case the normal force and p0 of each, their
differences from the full path, the corrections' estimate and what
``method = "auto"`` would choose.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from _common import machine_line  # noqa: E402

from bemcontact.bem import Displacement, ElasticBody, Fixed, LinearElastic  # noqa: E402
from bemcontact.contact import ContactPair, ContactProblem  # noqa: E402
from bemcontact.mesh import shapes  # noqa: E402
from bemcontact.multiscale import correction  # noqa: E402
from bemcontact.multiscale.pair import GridOptions, applicability, solve_on_grid  # noqa: E402

STEEL = LinearElastic(210000.0, 0.3)
R, APPROACH = 10.0, 0.03
A = math.sqrt(R * APPROACH)


def problem(fine: float, x0: float, thickness: float, search: float | None) -> ContactProblem:
    blk = shapes.graded_block((-10.0, -10.0, -thickness), (10.0, 10.0, 0.0), (x0, 0.0, 0.0),
                              fine_size=fine, coarse_size=2.5, fine_radius=max(1.1 * A, 2 * fine),
                              growth=0.45)
    cap = shapes.spherical_cap(R, R, apex=(x0, 0.0, 0.0), axis=1, fine_size=fine,
                               coarse_size=2.5, fine_radius=max(1.1 * A, 2 * fine), growth=0.45)
    block = ElasticBody(blk, STEEL, {"zmin": Fixed()}, name="block")
    sphere = ElasticBody(cap, STEEL, {"base": Displacement((0.0, 0.0, -APPROACH))},
                         name="sphere")
    pair = ContactPair("zmax", "contact", search_distance=search)
    return ContactProblem(block, sphere, pair)


def case(a_over_h: float, x0: float, thickness: float) -> dict:
    h = A / a_over_h
    t0 = time.perf_counter()
    full = problem(h, x0, thickness, 0.05).solve()
    t1 = time.perf_counter()
    P_full = full.normal_force
    p0_full = float(full.frame.pressure.max())
    coarse = problem(min(0.5, thickness / 2.0), x0, thickness, None)
    ms = solve_on_grid(coarse, options=GridOptions(grid_size=A / 25.0))
    t2 = time.perf_counter()
    app = applicability(ms, coarse)
    # the same grid with the corrections off: two half-spaces
    B = correction.BodyCorrection
    saved = B.matvec, B.low_rank, correction.near_field_blocks
    B.matvec = B.low_rank = lambda self, p: np.zeros_like(p)
    correction.near_field_blocks = lambda grid, *a, **k: np.zeros(
        (2 * grid.nx - 1, 2 * grid.ny - 1, 3, 3))
    try:
        hs = solve_on_grid(coarse, options=GridOptions(grid_size=A / 25.0))
    finally:
        B.matvec, B.low_rank, correction.near_field_blocks = saved
    P_ms, P_hs = ms.history[-1].force[2], hs.history[-1].force[2]
    return {
        "edge_over_a": (10.0 - x0) / A, "thickness_over_a": thickness / A,
        "P_full": P_full, "P_multiscale": P_ms, "P_halfspace": P_hs,
        "P_err_multiscale": P_ms / P_full - 1.0, "P_err_halfspace": P_hs / P_full - 1.0,
        "p0_err_multiscale": float(ms.history[-1].p[:, 2].max()) / p0_full - 1.0,
        "p0_err_halfspace": float(hs.history[-1].p[:, 2].max()) / p0_full - 1.0,
        "estimate": max(c.estimate for c in ms.corrections),
        "auto": "full" if app["reason"] else "multiscale", "reason": app["reason"],
        "full_s": t1 - t0, "multiscale_s": t2 - t1,
    }


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--a-over-h", type=float, default=8.0)
    ap.add_argument("--json", help="write all rows to this file")
    args = ap.parse_args(argv)
    print(machine_line())
    rows = []
    cases = [(10.0 - d * A, 10.0) for d in (10.0, 5.0, 3.0, 2.0)]
    cases += [(0.0, t * A) for t in (10.0, 4.0, 2.0, 1.0)]
    print(f"{'d/a':>5s} {'t/a':>5s} {'P full':>9s} {'P err ms':>9s} {'P err hs':>9s} "
          f"{'p0 err ms':>10s} {'p0 err hs':>10s} {'estimate':>9s} {'auto':>11s}")
    for x0, t in cases:
        r = case(args.a_over_h, x0, t)
        rows.append(r)
        print(f"{r['edge_over_a']:5.1f} {r['thickness_over_a']:5.1f} {r['P_full']:9.1f} "
              f"{r['P_err_multiscale']:9.2%} {r['P_err_halfspace']:9.2%} "
              f"{r['p0_err_multiscale']:10.2%} {r['p0_err_halfspace']:10.2%} "
              f"{r['estimate']:9.1e} {r['auto']:>11s}", flush=True)
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"machine": machine_line(), "rows": rows}, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
