"""How far two half-spaces are from the finite bodies: the full path on
``cases.sphere_on_block`` (frictionless, approach 0.03 mm of the sphere's
base towards the block's clamped base) against the contact grid with no
correction (two half-spaces, the same approach; then the full path's force).

    python benchmarks/grid_finite_body_effect.py [--a-over-h 12]

Prints one JSON line: the forces at the same approach, the half-space
approach at the full path's force, and p0 of both and of Hertz.  What the
finite bodies' corrections of the multiscale path have to supply is the
difference.
"""

from __future__ import annotations

import argparse
import json
import math
import time

import numpy as np
import scipy.fft

from bemcontact.halfspace import Compliance, Grid
from bemcontact.multiscale import GridInterface, PairOperator
from bemcontact.validation import cases
from bemcontact.validation.reference import contact as ref

APPROACH = 0.03


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--a-over-h", type=float, default=12.0)
    args = ap.parse_args(argv)
    aoh = args.a_over_h
    a_guess = math.sqrt(cases.SphereOnBlock().radius * APPROACH)
    h = a_guess / aoh
    s = cases.SphereOnBlock(size_profile=((0.0, h), (1.1 * a_guess, h)), growth=0.45)
    t0 = time.perf_counter()
    res = cases.sphere_on_block(h, APPROACH, friction_coefficient=0.0, setup=s).solve()
    full_s = time.perf_counter() - t0
    P_full = res.history[0].normal_force
    r, p, *_ = cases.radial_profile(res.history[0].frame)
    G = s.youngs_modulus / (2.0 * (1.0 + s.poisson_ratio))
    pair = Compliance.pair(G, s.poisson_ratio, G, s.poisson_ratio)
    nx = scipy.fft.next_fast_len(int(math.ceil(2.3 * aoh)))
    grid = Grid.centred(nx, nx, h, h)
    c = grid.centres
    rr = np.hypot(c[:, 0], c[:, 1])
    gap = s.radius - np.sqrt(s.radius ** 2 - rr ** 2)
    same_approach = GridInterface(PairOperator(grid, pair), gap, 0.0)
    same_approach.solve_increment([np.nan, np.nan, np.nan], [0.0, 0.0, -APPROACH])
    same_force = GridInterface(PairOperator(grid, pair), gap, 0.0)
    same_force.solve_increment([np.nan, np.nan, P_full], [0.0, 0.0, 0.0])
    P_grid = float(same_approach.force()[2])
    print(json.dumps({
        "a_over_h": aoh, "full_path_s": full_s, "frame_nodes": int(r.size),
        "P_full": P_full, "P_halfspaces_same_approach": P_grid,
        "P_rel_diff": P_grid / P_full - 1.0,
        "approach_full": APPROACH, "approach_halfspaces_same_P": float(-same_force.d[2]),
        "p0_full": float(p.max()), "p0_halfspaces_same_P": float(same_force.p[:, 2].max()),
        "p0_hertz": ref.hertz(P_full, s.radius, pair.contact_modulus).peak_pressure,
    }))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
