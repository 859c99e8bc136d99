"""Rolling on the contact grid against CONTACT's published figures.

    python benchmarks/rolling_contact_cases.py [--repeat 3] [--json FILE]

Three cases, each timed as the median of ``repeat`` runs in this process
(wall and CPU seconds, all threads), the machine and commit printed above the
table, peak RSS at the end:

* **one steady solve on a 50 x 50 grid**: CONTACT's spin case
  (examples/fastsim.inp: a = 8, b = 4 mm, η = −0.000625, φ = 0.000625 1/mm)
  on 50 x 50 cells over 1.1 × the ellipse, from the pressed state (the
  normal solve is timed apart);
* **a 30-point creep-force curve**: CONTACT's tractcurv case (48 x 44 cells,
  its first series' 30 creepages ξ from 1e-5 to 0.25), one pressed grid
  reused, each point from the previous point's solution;
* **the spin case on CONTACT's 44 x 44 grid**: F_y/(μ F_n) at the cell
  centres and with the spin's rigid slip a sixth of a cell downstream (as
  CONTACT takes it) against its −0.6074.

The curve's F_x/(μ F_n) at CONTACT's tabulated creepages is printed beside
its values (the same discretization: they agree to its printed digits).
CONTACT itself (Fortran) is not built here: its times are not compared.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import resource
import statistics
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from _common import machine_line, timed  # noqa: E402

from bemcontact.contact.rolling import Rolling  # noqa: E402
from bemcontact.halfspace import Compliance, Grid  # noqa: E402
from bemcontact.multiscale import GridInterface, GridRolling, PairOperator  # noqa: E402
from bemcontact.validation.reference import rolling as rr  # noqa: E402

NAN = math.nan
AXES = np.eye(3)
#: CONTACT's tractcurv.inp first series (absolute creepages).
CURVE = ([1e-5] + [round(0.0004 * k, 10) for k in range(1, 15)] + [0.006, 0.008, 0.010, 0.02, 0.03, 0.04,
                                                         0.05] +
         [round(0.075 + 0.025 * k, 10) for k in range(8)])


def pressed(case, cells, half_widths):
    pair = Compliance.pair(case["G"], case["nu"], case["G"], case["nu"])
    mx, my = cells
    grid = Grid.centred(mx, my, 2.0 * half_widths[0] / mx, 2.0 * half_widths[1] / my)
    c = grid.centres
    gi = GridInterface(PairOperator(grid, pair), case["A"] * c[:, 0] ** 2 +
                       case["B"] * c[:, 1] ** 2, case["mu"])
    rec = gi.solve_increment([NAN, NAN, case["Fn"]], [0.0, 0.0, 0.0])
    assert rec.converged, rec.message
    return gi


def roll(gi, case, creepage, spin, offset=0.0):
    ro = GridRolling(Rolling((1, 0, 0), creepage, spin), gi.grid, AXES, spin_offset=offset)
    rec = gi.solve_increment([NAN, NAN, case["Fn"]], [0.0, 0.0, 0.0], rolling=ro)
    assert rec.converged, rec.message
    F = gi.force()
    return F / (case["mu"] * F[2]), rec


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--json")
    ap.add_argument("--points", type=int, default=len(CURVE), help="creep-force points")
    args = ap.parse_args(argv)
    spin, curve = rr.CONTACT_SPIN, rr.CONTACT_CURVE
    print(machine_line())
    rows = {}

    w, c, _ = timed(lambda: pressed(spin, (50, 50), (8.8, 4.4)), args.repeat)
    rows["normal, 50 x 50"] = {"wall": w, "cpu": c}

    def steady():
        g = pressed(spin, (50, 50), (8.8, 4.4))
        t, u = time.perf_counter(), time.process_time()
        r, rec = roll(g, spin, (0.0, spin["eta"]), spin["phi"])
        return time.perf_counter() - t, time.process_time() - u, r, rec

    runs = [steady() for _ in range(args.repeat)]  # the rolling solve alone, median
    r, rec = runs[-1][2:]
    rows["steady rolling with spin, 50 x 50"] = {
        "wall": statistics.median(x[0] for x in runs), "cpu": statistics.median(x[1] for x in runs),
        "Fy/muFn": r[1], "newton": rec.iterations, "krylov": rec.krylov_iterations}

    values = CURVE[: args.points]

    def creep_curve():
        g = pressed(curve, curve["cells"], curve["half_widths"])
        t, u = time.perf_counter(), time.process_time()
        out = [roll(g, curve, (xi, 0.0), 0.0)[0][0] for xi in values]
        return time.perf_counter() - t, time.process_time() - u, out

    runs = [creep_curve() for _ in range(args.repeat)]  # the curve alone, median
    ratios = runs[-1][2]
    rows[f"creep-force curve, {len(values)} points, 48 x 44"] = {
        "wall": statistics.median(x[0] for x in runs), "cpu": statistics.median(x[1] for x in runs)}
    comparison = {xi: (ratios[values.index(xi)] if xi in values else None, want)
                  for xi, want in curve["Fx_over_muFn"].items()}

    g44 = pressed(spin, spin["cells"], (8.8, 4.4))
    centres = roll(g44, spin, (0.0, spin["eta"]), spin["phi"])[0][1]
    sixth = roll(g44, spin, (0.0, spin["eta"]), spin["phi"], 1.0 / 6.0)[0][1]

    print(f"{'case':44s} {'wall s':>8s}  {'CPU s':>8s}  notes")
    for name, row in rows.items():
        cpu = f"{row['cpu']:8.3f}"
        notes = ", ".join(f"{k} {v:.4g}" if isinstance(v, float) else f"{k} {v}"
                          for k, v in row.items() if k not in ("wall", "cpu"))
        print(f"{name:44s} {row['wall']:8.3f}  {cpu:>8s}  {notes}")
    print("creep-force curve against CONTACT (F_x/(mu F_n)):")
    for xi, (got, want) in comparison.items():
        print(f"  xi = {xi:.4f}: {'' if got is None else f'{got:+.5f}'}  CONTACT {want:+.4f}")
    print(f"spin case on 44 x 44: F_y/(mu F_n) {centres:+.5f} at the cell centres, "
          f"{sixth:+.5f} with CONTACT's sixth of a cell (CONTACT {spin['Fy_over_muFn']:+.4f})")
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
    print(f"peak RSS {peak:.0f} MB")
    result = {"machine": machine_line(), "rows": rows, "spin_44": [centres, sixth],
              "curve": {str(k): v for k, v in comparison.items()}, "peak_mb": peak}
    if args.json:
        with open(args.json, "w") as f:
            json.dump(result, f, indent=1)
    return result


if __name__ == "__main__":
    main()
