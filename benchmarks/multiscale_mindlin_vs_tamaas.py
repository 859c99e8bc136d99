"""Cattaneo–Mindlin on finite bodies by the multiscale path, the whole run,
against Tamaas at the same a/h, in one run.

    python benchmarks/multiscale_mindlin_vs_tamaas.py [--a-over-h 12 25 50 100]
        [--repeat 3] [--tamaas-max-a-over-h 50] [--no-install] [--json FILE]

The problem is ``hertz_mindlin_vs_tamaas.py``'s: the steel hemisphere
(R = 10 mm) on the steel block (20 × 20 × 10 mm, base clamped), approach
0.03 mm, μ = 0.3, then Q = 0.02 μP (one increment) and Q = 0.5 μP (4
increments) on the sphere's platen.  Here the bodies are meshed at the scale
of their geometry (0.5 mm within 1 mm of the contact, growing by 0.45 per
mm to 2.5 mm: 778 + 403 nodes, whatever a/h) and the contact zone is a grid
of cells h = a/(a/h) (``grid_size``): :func:`bemcontact.multiscale.pair.
solve_on_grid`, timed from the meshing (gmsh) to the last increment, in its
own process (peak RSS), medians of ``--repeat`` runs.

Errors against the closed forms, measured as the full benchmark measures
them: Hertz p0 (largest cell pressure) and the fitted contact radius at step
P; at Q = 0.5 μP the shear profile inside 0.9a (relative L2, cell areas as
weights), the stick radius (area-equivalent) and the tangential approach
(the platen's translation, the bodies' linear compliance measured at the
small step and replaced by the contact's S/(8a): ``cases.tangential_approach``).
Tamaas as in ``grid_mindlin_vs_tamaas.py``.
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

from _common import machine_line, run_median  # noqa: E402

MU, RATIO, SMALL, APPROACH = 0.3, 0.5, 0.02, 0.03


def one(a_over_h: float) -> dict:
    """One whole multiscale run at ``a_over_h``."""
    import bemcontact as bc
    from bemcontact.bench import peak_rss_mb
    from bemcontact.contact.law import STICK
    from bemcontact.multiscale.pair import GridOptions, applicability, solve_on_grid
    from bemcontact.validation import cases
    from bemcontact.validation.reference import contact as ref

    cpu0, wall0 = time.process_time(), time.perf_counter()
    s = cases.SphereOnBlock(fine_radius=1.0, growth=0.45)
    a_guess = math.sqrt(s.radius * APPROACH)
    prob = cases.sphere_on_block(0.5, APPROACH, friction_coefficient=MU, setup=s)
    p_guess = ref.hertz_force(APPROACH, s.radius, s.contact_modulus)
    steps = ([bc.LoadStep(label="P")]
             + cases.tangential_steps([SMALL * MU * p_guess], APPROACH, increments=1,
                                      label="small")
             + cases.tangential_steps([RATIO * MU * p_guess], APPROACH, increments=4))
    res = solve_on_grid(prob, steps, GridOptions(grid_size=a_guess / a_over_h))
    cpu, wall = time.process_time() - cpu0, time.perf_counter() - wall0
    c = res.grid.centres
    r = np.hypot(c[:, 0], c[:, 1])
    A = res.grid.cell_area
    first, top = res.history[0], res.history[2]
    P = first.force[2]
    hz = ref.hertz(P, s.radius, s.contact_modulus)
    a = hz.contact_radius
    inner = r < 0.9 * a
    fit, *_ = np.linalg.lstsq(np.column_stack([np.ones(inner.sum()), r[inner] ** 2]),
                              first.p[inner, 2] ** 2, rcond=None)
    a_fit = math.sqrt(-fit[0] / fit[1])
    P2 = top.force[2]
    hz2 = ref.hertz(P2, s.radius, s.contact_modulus)
    Q = np.array([-st.force[0] for st in res.history])  # the platen's force
    U = np.array([st.d[0] for st in res.history])  # the platen's translation
    S = s.tangential_compliance_factor
    d_num = cases.tangential_approach(Q, U, hz2.contact_radius, S)[2]
    d_exact = ref.cattaneo_mindlin_displacement(Q[2], MU, P2, hz2.contact_radius, S)
    inner2 = r < 0.9 * hz2.contact_radius
    q = -top.p[inner2, 0]  # on body 1, as the full benchmark measures it
    q_exact = ref.cattaneo_mindlin_traction(r[inner2], hz2, Q[2], MU)
    c_num = math.sqrt((top.state == STICK).sum() * A / math.pi)
    c_front = cases.stick_front_radius(c[:, :2], top.p[:, 2], np.hypot(top.p[:, 0], top.p[:, 1]),
                                       top.state, np.full(r.size, A), MU)
    c_exact = ref.cattaneo_mindlin_stick_radius(hz2.contact_radius, Q[2], MU, P2)
    app = applicability(res, prob)
    return {
        "code": "bemcontact-multiscale", "a_over_h": a_over_h, "cells": res.grid.size,
        "nx": res.grid.nx, "nodes": [b.discretization.n_points for b in prob.bodies],
        "P": P, "p0_err": float(first.p[:, 2].max() / hz.peak_pressure - 1.0),
        "a_err": a_fit / a - 1.0, "q_ratio": Q[2] / (MU * P2),
        "q_l2": float(np.linalg.norm(q - q_exact) / np.linalg.norm(q_exact)),
        "c_err": c_num / c_exact - 1, "c_front_err": c_front / c_exact - 1,
        "dt_err": d_num / d_exact - 1.0,
        "estimate": max(c.estimate for c in res.corrections), "applies": app["reason"] == "",
        "newton": [x.iterations for x in res.records],
        "krylov": [x.krylov_iterations for x in res.records],
        "timings": res.timings, "cpu_s": cpu, "wall_s": wall, "peak_rss_mb": peak_rss_mb(),
    }


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--a-over-h", type=float, nargs="+", default=[12.0, 25.0, 50.0, 100.0])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--tamaas-max-a-over-h", type=float, default=50.0)
    ap.add_argument("--no-install", action="store_true")
    ap.add_argument("--json", help="write all rows to this file")
    ap.add_argument("--one", type=float, help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.one is not None:
        print(json.dumps(one(args.one), default=float))
        return 0
    import _tamaas_side as tamaas_side
    from grid_mindlin_vs_tamaas import tamaas_row

    have_tamaas = tamaas_side.tamaas_available(install=not args.no_install)
    print(machine_line())
    print(f"{'code':22s} {'a/h':>5s} {'cells':>7s} {'p0 err':>8s} {'a err':>7s} {'q L2':>7s} "
          f"{'c err':>7s} {'dt err':>8s} {'CPU s':>8s} {'wall s':>8s} {'MB':>7s}")
    rows = []
    for aoh in args.a_over_h:
        row = run_median(__file__, aoh, args.repeat)
        rows.append(row)
        print(f"{'bemcontact-multiscale':22s} {aoh:5.0f} {row['cells']:7d} {row['p0_err']:8.2%} "
              f"{row['a_err']:7.2%} {row['q_l2']:7.2%} {row['c_err']:7.2%} "
              f"{row['dt_err']:8.2%} {row['cpu_s']:8.2f} {row['wall_s']:8.2f} "
              f"{row['peak_rss_mb']:7.0f}  c front {row['c_front_err']:.2%} Newton {row['newton']} "
              f"est {row['estimate']:.1g}",
              flush=True)
        if have_tamaas and aoh <= args.tamaas_max_a_over_h:
            t = tamaas_row(aoh)
            rows.append(t)
            print(f"{'tamaas':22s} {aoh:5.0f} {t['n_nodes']:7d} {'':>8s} {'':>7s} "
                  f"{t['q_l2_error']:7.2%} {t['c_num'] / t['c_exact'] - 1:7.2%} "
                  f"{t['delta_t_num'] / t['delta_t_exact'] - 1:8.2%} {t['cpu_seconds']:8.2f} "
                  f"{t['wall_seconds']:8.2f} {'':>7s}  CPU ratio "
                  f"{row['cpu_s'] / t['cpu_seconds']:.2f}", flush=True)
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"machine": machine_line(), "rows": rows}, f, indent=1, default=str)
    return 0


if __name__ == "__main__":
    sys.exit(main())
