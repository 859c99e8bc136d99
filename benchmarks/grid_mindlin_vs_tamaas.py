"""Cattaneo–Mindlin on the contact grid (the multiscale path's interface
solve, two identical half-spaces) against Tamaas at the same a/h, in one run.

    python benchmarks/grid_mindlin_vs_tamaas.py [--a-over-h 12 25 50 100]
        [--tamaas-max-a-over-h 50] [--no-install] [--json FILE]

The problem is the one of ``hertz_mindlin_vs_tamaas.py``'s Cattaneo–Mindlin
row: steel (E = 210 GPa, ν = 0.3) sphere R = 10 mm on steel, P from an
approach of 0.03 mm (a ≈ 0.555 mm), μ = 0.3, then Q = 0.5 μP, here on two
half-spaces (no finite-body correction: this measures the interface solve
that the multiscale path runs on the grid).  bemcontact: a paraboloid gap
on a square grid 2.3a wide (cells h = a/(a/h), the side an FFT-friendly
count), P in one increment, Q in 4 (force control of all three components:
the path of the full benchmark).  Tamaas: ``_tamaas_side.cattaneo_mindlin``
(periodic L = 8a, one total-load solve, ν_T = 0.5 so that it is decoupled
like the closed form; its run-length search excluded from its time).

Each bemcontact size runs in its own process (its peak RSS is that size's);
times are ``time.process_time`` (CPU, all threads) and wall; medians of
``--repeat`` runs.  Errors against the closed forms: p0, the shear profile
inside 0.9a (relative L2), the stick radius (area-equivalent radius of the
stick cells) and the tangential approach.
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

E, NU, R, MU, APPROACH, RATIO, INCREMENTS = 210000.0, 0.3, 10.0, 0.3, 0.03, 0.5, 4


def one(a_over_h: float) -> dict:
    """One bemcontact grid solve at ``a_over_h``: errors, Newton and Krylov
    iterations, CPU and wall seconds (grid set-up included), peak RSS."""
    import scipy.fft

    from bemcontact.bench import peak_rss_mb
    from bemcontact.contact.law import STICK
    from bemcontact.halfspace import Compliance, Grid
    from bemcontact.multiscale import GridInterface, PairOperator
    from bemcontact.validation.reference import contact as ref

    G = E / (2.0 * (1.0 + NU))
    pair = Compliance.pair(G, NU, G, NU)
    P = ref.hertz_force(APPROACH, R, pair.contact_modulus)
    hz = ref.hertz(P, R, pair.contact_modulus)
    a = hz.contact_radius
    Q = RATIO * MU * P
    cpu0, wall0 = time.process_time(), time.perf_counter()
    h = a / a_over_h
    nx = scipy.fft.next_fast_len(int(math.ceil(2.3 * a_over_h)))
    grid = Grid.centred(nx, nx, h, h)
    c = grid.centres
    gap = (c[:, 0] ** 2 + c[:, 1] ** 2) / (2.0 * R)
    gi = GridInterface(PairOperator(grid, pair), gap, MU)
    recs = [gi.solve_increment([0.0, 0.0, P], [0.0, 0.0, 0.0])]
    for i in range(1, INCREMENTS + 1):
        recs.append(gi.solve_increment([Q * i / INCREMENTS, 0.0, P], [0.0, 0.0, 0.0]))
    cpu, wall = time.process_time() - cpu0, time.perf_counter() - wall0
    r = np.hypot(c[:, 0], c[:, 1])
    inner = r < 0.9 * a
    q_exact = ref.cattaneo_mindlin_traction(r[inner], hz, Q, MU)
    c_num = math.sqrt((gi.state() == STICK).sum() * gi.area / math.pi)
    S = ref.tangential_compliance_factor(G, NU, G, NU)
    return {
        "code": "bemcontact-grid", "a_over_h": a_over_h, "cells": grid.size, "nx": nx,
        "converged": all(x.converged for x in recs),
        "p0_err": float(gi.p[:, 2].max() / hz.peak_pressure - 1.0),
        "q_l2": float(np.linalg.norm(gi.p[inner, 0] - q_exact) / np.linalg.norm(q_exact)),
        "c_err": c_num / ref.cattaneo_mindlin_stick_radius(a, Q, MU, P) - 1.0,
        "dt_err": abs(gi.d[0]) / ref.cattaneo_mindlin_displacement(Q, MU, P, a, S) - 1.0,
        "newton": [x.iterations for x in recs], "krylov": [x.krylov_iterations for x in recs],
        "cpu_s": cpu, "wall_s": wall, "peak_rss_mb": peak_rss_mb(),
    }


def tamaas_row(a_over_h: float) -> dict:
    import _tamaas_side as tamaas_side

    from bemcontact.validation.reference import contact as ref

    E_star = E / (2.0 * (1.0 - NU * NU))
    P = ref.hertz_force(APPROACH, R, E_star)
    return tamaas_side.cattaneo_mindlin(R, E, NU, MU, P, RATIO, a_over_h)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--a-over-h", type=float, nargs="+", default=[12.0, 25.0, 50.0, 100.0])
    ap.add_argument("--tamaas-max-a-over-h", type=float, default=50.0)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--no-install", action="store_true")
    ap.add_argument("--json", help="write all rows to this file")
    ap.add_argument("--one", type=float, help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.one is not None:
        print(json.dumps(one(args.one)))
        return 0
    import _tamaas_side as tamaas_side

    have_tamaas = tamaas_side.tamaas_available(install=not args.no_install)
    print(machine_line())
    rows = []
    head = (f"{'code':16s} {'a/h':>5s} {'cells':>7s} {'p0 err':>8s} {'q L2':>7s} {'c err':>7s} "
            f"{'dt err':>8s} {'CPU s':>8s} {'wall s':>8s} {'MB':>7s}  iterations")
    print(head)
    for aoh in args.a_over_h:
        row = run_median(__file__, aoh, args.repeat)
        rows.append(row)
        print(f"{'bemcontact-grid':16s} {aoh:5.0f} {row['cells']:7d} {row['p0_err']:8.2%} "
              f"{row['q_l2']:7.2%} {row['c_err']:7.2%} {row['dt_err']:8.3%} {row['cpu_s']:8.2f} "
              f"{row['wall_s']:8.2f} {row['peak_rss_mb']:7.0f}  Newton {row['newton']}, "
              f"Krylov {row['krylov']}", flush=True)
        if have_tamaas and aoh <= args.tamaas_max_a_over_h:
            t = tamaas_row(aoh)
            rows.append(t)
            ratio = row["cpu_s"] / t["cpu_seconds"]
            print(f"{'tamaas':16s} {aoh:5.0f} {t['n_nodes']:7d} {'':>8s} {t['q_l2_error']:7.2%} "
                  f"{t['c_num'] / t['c_exact'] - 1:7.2%} "
                  f"{t['delta_t_num'] / t['delta_t_exact'] - 1:8.3%} {t['cpu_seconds']:8.2f} "
                  f"{t['wall_seconds']:8.2f} {'':>7s}  CPU ratio bemcontact/Tamaas {ratio:.2f}",
                  flush=True)
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"machine": machine_line(), "rows": rows}, f, indent=1, default=str)
    return 0


if __name__ == "__main__":
    sys.exit(main())
