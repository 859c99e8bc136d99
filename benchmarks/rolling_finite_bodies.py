"""Rolling where the half-space is wrong: a ball rolling along a block's
edge and on a thin layer, by the full path (both bodies meshed), by the
grid with the bodies' corrections and by two half-spaces (the grid with the
corrections off).

    python benchmarks/rolling_finite_bodies.py [--a-over-h 6] [--json FILE]

The steel sphere (R = 10 mm) pressed 0.03 mm (a ≈ 0.55 mm, F_n ≈ 2,650 N)
on a steel block 20 × 20 mm whose base is clamped, μ = 0.3, rolled in steady
state along y (parallel to the block's x = +10 edge) with creepage ξ = 0
and ξ = −0.0005: the apex d = 10, 3, 2 contact radii from that edge (block
10 mm thick), or centred on a block t = 2 contact radii thick.  Full path:
both bodies meshed at h = a/(a/h) within 1.1a of the apex.  Grid: the bodies
meshed at 0.5 mm near the apex (at most half the layer's thickness), cells
of a/25.  Prints per case F_n and the creep force F_y of each path at both
creepages and their slope F(−0.0005) − F(0).
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
from bemcontact.contact import ContactPair, ContactProblem, LoadStep, Rolling  # noqa: E402
from bemcontact.mesh import shapes  # noqa: E402
from bemcontact.multiscale import correction  # noqa: E402
from bemcontact.multiscale.pair import GridOptions, solve_on_grid  # noqa: E402

STEEL = LinearElastic(210000.0, 0.3)
R, APPROACH, MU = 10.0, 0.03, 0.3
A = math.sqrt(R * APPROACH)
XI = (0.0, -0.0005)


def problem(fine: float, x0: float, thickness: float, search: float | None) -> ContactProblem:
    radius = max(1.1 * A, 2 * fine)
    blk = shapes.graded_block((-10.0, -10.0, -thickness), (10.0, 10.0, 0.0), (x0, 0.0, 0.0),
                              fine_size=fine, coarse_size=2.5, fine_radius=radius, growth=0.45)
    cap = shapes.spherical_cap(R, R, apex=(x0, 0.0, 0.0), axis=1, fine_size=fine,
                               coarse_size=2.5, fine_radius=radius, growth=0.45)
    block = ElasticBody(blk, STEEL, {"zmin": Fixed()}, name="block")
    sphere = ElasticBody(cap, STEEL, {"base": Displacement((0.0, 0.0, -APPROACH))},
                         name="sphere")
    return ContactProblem(block, sphere, ContactPair("zmax", "contact", friction_coefficient=MU,
                                                     search_distance=search))


def steps(xi: float) -> list:
    return [LoadStep(label="pressed"),
            LoadStep(label="rolling", rolling=Rolling((0, 1, 0), (xi, 0.0)))]


def grid_forces(coarse, off: bool) -> list:
    B = correction.BodyCorrection
    saved = B.matvec, B.low_rank, correction.near_field_blocks
    if off:
        B.matvec = B.low_rank = lambda self, p: np.zeros_like(p)
        correction.near_field_blocks = lambda grid, *a, **k: np.zeros(
            (2 * grid.nx - 1, 2 * grid.ny - 1, 3, 3))
    try:
        out = []
        for xi in XI:
            r = solve_on_grid(coarse, steps(xi), GridOptions(grid_size=A / 25.0))
            out.append((r.history[-1].force[2], r.history[-1].rolling["creep_force"][0]))
        return out
    finally:
        B.matvec, B.low_rank, correction.near_field_blocks = saved


def case(a_over_h: float, x0: float, thickness: float) -> dict:
    h = A / a_over_h
    t0 = time.perf_counter()
    full = []
    prob = problem(h, x0, thickness, 0.05)
    for xi in XI:
        r = prob.solve(steps=steps(xi))
        full.append((r.normal_force, r.rolling["creep_force"][0]))
    t1 = time.perf_counter()
    coarse = problem(min(0.5, thickness / 2.0), x0, thickness, None)
    ms = grid_forces(coarse, off=False)
    hs = grid_forces(coarse, off=True)
    t2 = time.perf_counter()
    row = {"edge_over_a": (10.0 - x0) / A, "thickness_over_a": thickness / A,
           "full_s": t1 - t0, "grid_s": t2 - t1}
    for name, v in (("full", full), ("grid", ms), ("halfspace", hs)):
        row[f"Fn_{name}"] = v[0][0]
        row[f"F0_{name}"] = v[0][1]
        row[f"F_{name}"] = v[1][1]
        row[f"slope_{name}"] = v[1][1] - v[0][1]
    return row


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--a-over-h", type=float, default=6.0)
    ap.add_argument("--json")
    ap.add_argument("--cases", default="10,3,2,t2", help="d/a values and tN for a layer")
    args = ap.parse_args(argv)
    print(machine_line(f", full path a/h = {args.a_over_h:g}"))
    rows = []
    for c in args.cases.split(","):
        if c.startswith("t"):
            rows.append(case(args.a_over_h, 0.0, float(c[1:]) * A))
        else:
            rows.append(case(args.a_over_h, 10.0 - float(c) * A, 10.0))
    print(f"{'d/a':>5s} {'t/a':>5s} | {'F_n full':>9s} {'grid':>8s} {'hs':>8s} | "
          f"F_y(ξ=0): {'full':>7s} {'grid':>7s} {'hs':>7s} | slope: {'full':>7s} {'grid':>7s} "
          f"{'hs':>7s}")
    for r in rows:
        print(f"{r['edge_over_a']:5.1f} {r['thickness_over_a']:5.1f} | {r['Fn_full']:9.1f} "
              f"{r['Fn_grid']:8.1f} {r['Fn_halfspace']:8.1f} | {r['F0_full']:16.2f} "
              f"{r['F0_grid']:7.2f} {r['F0_halfspace']:7.2f} | {r['slope_full']:14.2f} "
              f"{r['slope_grid']:7.2f} {r['slope_halfspace']:7.2f}")
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"machine": machine_line(), "rows": rows}, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
