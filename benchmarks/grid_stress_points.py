"""Stresses on the multiscale path: 1,000,000 points below the contact.

    python benchmarks/grid_stress_points.py [--points 1000000] [--json FILE]

The Cattaneo–Mindlin example solved on the grid
(``examples/cattaneo_mindlin_multiscale.toml``: coarse bodies, cells of a/25),
then the block's stresses from ``GridResult.stresses`` (the half-space field of
the grid tractions below the block's own surface) at:

* a box of points below every cell centre of the grid at ``points / cells``
  depths from 0.02a to 3a (the points a user's box gives when it lies on the
  cell centres: each depth is one FFT layer);
* 2,000 points drawn uniformly (seed 0) in |x|, |y| <= 1.5a, 0.02a <= depth <=
  3a (the direct sum over the cells, per point).

Each is timed as the median of three calls (wall and CPU seconds, all
threads), in one process whose peak RSS is reported; the machine and commit
are printed above the table.  As a check of the field: the largest Tresca
stress of the box against Hertz's 0.310 p0 (the first load step is the normal
load alone; the tangential load raises it a little).
"""

from __future__ import annotations

import argparse
import json
import os
import pathlib
import resource
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from _common import machine_line, timed  # noqa: E402

EXAMPLE = pathlib.Path(__file__).resolve().parents[1] / "examples" / "cattaneo_mindlin_multiscale.toml"
REPEAT = 3
SAMPLE = 2000


def one(points: int, repeat: int = REPEAT, example=EXAMPLE) -> dict:
    from bemcontact.halfspace import tresca
    from bemcontact.problemfile import load_problem
    from bemcontact.validation.reference import contact as ref

    problem = load_problem(example)
    result = problem.solve()
    g = result.grid
    P = float(result.history[0].force[2])
    hz = ref.hertz(P, 10.0, ref.effective_modulus(210e3, 0.3, 210e3, 0.3))
    a, p0 = hz.contact_radius, hz.peak_pressure
    depths = np.linspace(0.02 * a, 3.0 * a, max(1, points // g.size))
    c = g.centres
    zeta1 = result.surfaces[0]
    from bemcontact.multiscale.surface import quartic_terms

    top = quartic_terms(c[:, 0], c[:, 1]) @ zeta1  # the block's surface above each cell
    local = np.concatenate([np.column_stack([c[:, :2], top - d]) for d in depths])
    box = result.origin + local @ result.axes
    wall, cpu, s = timed(lambda: result.stresses("block", box), repeat)
    rng = np.random.default_rng(0)
    xy = rng.uniform(-1.5 * a, 1.5 * a, (SAMPLE, 2))
    d = rng.uniform(0.02 * a, 3.0 * a, SAMPLE)
    z = quartic_terms(xy[:, 0], xy[:, 1]) @ zeta1 - d
    scattered = result.origin + np.column_stack([xy, z]) @ result.axes
    swall, scpu, _ = timed(lambda: result.stresses("block", scattered), repeat)
    return {"points": int(len(box)), "cells": int(g.size), "depths": int(depths.size),
            "wall_s": wall, "cpu_s": cpu, "per_point_us": 1e6 * wall / len(box),
            "scattered": SAMPLE, "scattered_wall_s": swall, "scattered_cpu_s": scpu,
            "scattered_per_point_us": 1e6 * swall / SAMPLE,
            "tresca_max_p0": float(tresca(s).max() / p0),
            "peak_rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--points", type=int, default=1_000_000)
    ap.add_argument("--json", help="also write the row as JSON to this file")
    args = ap.parse_args()
    row = one(args.points)
    print(machine_line())
    print()
    print("| points (box on cell centres) | cells × depths | wall s | CPU s | µs/point | "
          "scattered points: µs/point | largest Tresca / p0 | peak RSS MB |")
    print("|---|---|---|---|---|---|---|---|")
    print(f"| {row['points']:,} | {row['cells']} × {row['depths']} | {row['wall_s']:.2f} | "
          f"{row['cpu_s']:.2f} | {row['per_point_us']:.2f} | "
          f"{row['scattered_per_point_us']:.0f} | {row['tresca_max_p0']:.4f} | "
          f"{row['peak_rss_mb']:.0f} |")
    if args.json:
        pathlib.Path(args.json).write_text(json.dumps(row, indent=2) + "\n")


if __name__ == "__main__":
    main()
