"""The multiscale path against the full path on the same finite bodies:
Cattaneo–Mindlin loading of the benchmark's sphere on a block, both paths
at the same a/h.

    python benchmarks/multiscale_vs_full.py [--a-over-h 12 25] [--json FILE]

The problem is ``multiscale_mindlin_vs_tamaas.py``'s: the steel hemisphere
(R = 10 mm) on the steel block (20 × 20 × 10 mm, base clamped), approach
0.03 mm, μ = 0.3, then Q = 0.02 μP (one increment) and Q = 0.5 μP (4
increments) on the sphere's platen.  Full path: both bodies meshed at h =
a/(a/h) within 1.1a of the contact (a/h = 25: about 4 min and 5 GB).
Multiscale path: the bodies meshed at 0.5 mm near the contact (778 + 403
nodes), cells of h.  Compared, as docs/validation.md reports them: the
normal force at step P; the pressure at step P and the shear at Q = 0.5 μP,
rms differences inside 0.9a at the full path's frame nodes (the grid's cell
values interpolated bilinearly), in units of the full path's p0; the stick
radius of each from the area of its stick nodes or cells, and from the
traction at its stick–slip front (``cases.stick_front_radius``).  Accuracy only:
the wall times are printed, not medians.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
import time

import numpy as np
import scipy.interpolate

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from _common import machine_line  # noqa: E402

import bemcontact as bc  # noqa: E402
from bemcontact.contact.law import STICK  # noqa: E402
from bemcontact.multiscale.pair import GridOptions, applicability, solve_on_grid  # noqa: E402
from bemcontact.validation import cases  # noqa: E402
from bemcontact.validation.reference import contact as ref  # noqa: E402

MU, RATIO, SMALL, APPROACH = 0.3, 0.5, 0.02, 0.03


def _steps(p_guess: float) -> list:
    return ([bc.LoadStep(label="P")]
            + cases.tangential_steps([SMALL * MU * p_guess], APPROACH, increments=1,
                                     label="small")
            + cases.tangential_steps([RATIO * MU * p_guess], APPROACH, increments=4))


def _at(grid, values: np.ndarray, xy: np.ndarray) -> np.ndarray:
    """Cell values (n,) interpolated bilinearly at frame points xy (m, 2)."""
    x = grid.origin[0] + (np.arange(grid.nx) + 0.5) * grid.dx
    y = grid.origin[1] + (np.arange(grid.ny) + 0.5) * grid.dy
    f = scipy.interpolate.RegularGridInterpolator((x, y), values.reshape(grid.nx, grid.ny))
    return f(np.column_stack([np.clip(xy[:, 0], x[0], x[-1]), np.clip(xy[:, 1], y[0], y[-1])]))


def case(a_over_h: float) -> dict:
    s = cases.SphereOnBlock()
    a_guess = math.sqrt(s.radius * APPROACH)
    h = a_guess / a_over_h
    steps = _steps(ref.hertz_force(APPROACH, s.radius, s.contact_modulus))
    t0 = time.perf_counter()
    fine = cases.SphereOnBlock(size_profile=((0.0, h), (1.1 * a_guess, h)), growth=0.45)
    full = cases.sphere_on_block(h, APPROACH, friction_coefficient=MU, setup=fine).solve(
        steps=steps)
    t1 = time.perf_counter()
    coarse = cases.sphere_on_block(0.5, APPROACH, friction_coefficient=MU,
                                   setup=cases.SphereOnBlock(fine_radius=1.0, growth=0.45))
    ms = solve_on_grid(coarse, steps, GridOptions(grid_size=h))
    t2 = time.perf_counter()
    g = ms.grid
    f0, f2 = full.history[0].frame, full.history[2].frame
    # the full path's frame nodes in the grid's frame
    xy0 = ((f0.points - ms.origin) @ ms.axes.T)[:, :2]
    xy2 = ((f2.points - ms.origin) @ ms.axes.T)[:, :2]
    a = ref.hertz(full.history[0].normal_force, s.radius, s.contact_modulus).contact_radius
    p0 = float(f0.pressure.max())
    in0 = np.hypot(*xy0.T) < 0.9 * a
    in2 = np.hypot(*xy2.T) < 0.9 * a
    p_ms = _at(g, ms.history[0].p[:, 2], xy0)
    # the frame's tangential traction acts on body 2, as the grid's p does
    q_full = f2.tangential_traction[:, 0]
    q_ms = _at(g, ms.history[2].p[:, 0], xy2)
    c_full = cases.stick_radius(f2)
    c_ms = math.sqrt((ms.history[2].state == STICK).sum() * g.cell_area / math.pi)
    top = ms.history[2]
    front_full = cases.stick_front_radius(xy2, f2.pressure,
                                          np.linalg.norm(f2.tangential_traction, axis=1),
                                          f2.state, f2.weights, MU)
    front_ms = cases.stick_front_radius(g.centres[:, :2], top.p[:, 2],
                                        np.hypot(top.p[:, 0], top.p[:, 1]), top.state,
                                        np.full(g.size, g.cell_area), MU)
    P_full, P_ms = full.history[0].normal_force, float(ms.history[0].force[2])
    return {
        "a_over_h": a_over_h, "P_full": P_full, "P_multiscale": P_ms,
        "P_diff": P_ms / P_full - 1.0,
        "p_rms_diff": float(np.sqrt(np.mean((p_ms[in0] - f0.pressure[in0]) ** 2)) / p0),
        "q_rms_diff": float(np.sqrt(np.mean((q_ms[in2] - q_full[in2]) ** 2)) / p0),
        "c_full": c_full, "c_multiscale": c_ms, "c_diff": c_ms / c_full - 1.0,
        "c_front_full": front_full, "c_front_multiscale": front_ms,
        "c_front_diff": front_ms / front_full - 1.0,
        "estimate": max(c.estimate for c in ms.corrections),
        "applies": applicability(ms, coarse)["reason"] == "",
        "full_s": t1 - t0, "multiscale_s": t2 - t1,
    }


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--a-over-h", type=float, nargs="+", default=[12.0, 25.0])
    ap.add_argument("--json", help="write all rows to this file")
    args = ap.parse_args(argv)
    print(machine_line())
    print(f"{'a/h':>5s} {'P full':>9s} {'P ms':>9s} {'P diff':>8s} {'p rms':>8s} "
          f"{'q rms':>8s} {'c diff':>8s} {'c front':>8s} {'estimate':>9s} {'full s':>7s} "
          f"{'ms s':>6s}")
    rows = []
    for aoh in args.a_over_h:
        r = case(aoh)
        rows.append(r)
        print(f"{aoh:5.0f} {r['P_full']:9.1f} {r['P_multiscale']:9.1f} {r['P_diff']:8.2%} "
              f"{r['p_rms_diff']:8.2%} {r['q_rms_diff']:8.2%} {r['c_diff']:8.2%} "
              f"{r['c_front_diff']:8.2%} "
              f"{r['estimate']:9.1e} {r['full_s']:7.1f} {r['multiscale_s']:6.1f}", flush=True)
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"machine": machine_line(), "rows": rows}, f, indent=1, default=float)
    return 0


if __name__ == "__main__":
    sys.exit(main())
