"""The founding paper's two cubes under mesh refinement (docs/validation.md).

Lower cube [0,2]^2 x [0,2] with n^3 quad4 elements, upper [0,2]^2 x [2,4]
with (n-1)^3 (non-matching interface), E1 = 1e4 MPa, nu = 0.3, mu = 0.1;
z = 0 fixed, z = 4 moved by (0, 0, -0.04) mm.  Similar (E2 = 1e4) and
dissimilar (E2 = 1e8) cases; the similar pair is compared with one 2 x 2 x 4
column (n x n x 2n elements) solved by the one-body solver.

Prints a Markdown table per case: n, frame nodes, normal force, change from
the previous mesh, Newton iterations, stick / slip / open frame nodes, the
stick zone's extent (largest distance of a stick node from the centre), and
the wall time.

Usage:  python examples/two_cubes_refinement.py [--sizes 4,5,6,8,12]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import bemcontact as bc


def pair(n: int, E2: float) -> bc.ContactResult:
    lower = bc.ElasticBody(
        bc.box((0, 0, 0), (2, 2, 2), n), bc.LinearElastic(1.0e4, 0.3),
        {"zmin": bc.Displacement((0.0, 0.0, 0.0))}, name="lower",
    )
    upper = bc.ElasticBody(
        bc.box((0, 0, 2), (2, 2, 4), n - 1), bc.LinearElastic(E2, 0.3),
        {"zmax": bc.Displacement((0.0, 0.0, -0.04))}, name="upper",
    )
    return bc.ContactProblem(lower, upper, bc.ContactPair("zmax", "zmin", 0.1)).solve()


def column(n: int) -> float:
    body = bc.ElasticBody(
        bc.box((0, 0, 0), (2, 2, 4), (n, n, 2 * n)), bc.LinearElastic(1.0e4, 0.3),
        {"zmin": bc.Displacement((0.0, 0.0, 0.0)), "zmax": bc.Displacement((0.0, 0.0, -0.04))},
    )
    return float(-body.solve().reaction("zmax")[2])


def row(n: int, E2: float) -> dict:
    t0 = time.perf_counter()
    res = pair(n, E2)
    wall = time.perf_counter() - t0
    fr = res.frame
    stick = fr.state == 1
    extent = float(np.linalg.norm(fr.points[stick, :2] - 1.0, axis=1).max()) if stick.any() else None
    out = {
        "n": n,
        "frame_nodes": int(fr.state.size),
        "normal_force": res.normal_force,
        "iterations": res.newton_iterations,
        **fr.counts(),
        "stick_extent": extent,
        "wall_s": wall,
    }
    if E2 == 1.0e4:
        out["column_force"] = column(n)
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--sizes", default="4,5,6,8,12")
    sizes = [int(s) for s in ap.parse_args().sizes.split(",")]
    for label, E2 in (("similar", 1.0e4), ("dissimilar", 1.0e8)):
        print(f"\n{label} (E2 = {E2:g} MPa)\n")
        head = "| n | frame nodes | normal force N | change N | Newton it. | stick | slip | open | stick extent mm | wall s |"
        if E2 == 1.0e4:
            head += " column N | pair/column − 1 |"
        print(head)
        print("|" + "---:|" * (head.count("|") - 1))
        prev = None
        for n in sizes:
            r = row(n, E2)
            ch = "" if prev is None else f"{r['normal_force'] - prev:+.3f}"
            prev = r["normal_force"]
            ext = "—" if r["stick_extent"] is None else f"{r['stick_extent']:.3g}"
            line = (f"| {n} | {r['frame_nodes']} | {r['normal_force']:.3f} | {ch} | {r['iterations']} | "
                    f"{r['stick']} | {r['slip']} | {r['open']} | {ext} | {r['wall_s']:.1f} |")
            if "column_force" in r:
                line += f" {r['column_force']:.3f} | {r['normal_force'] / r['column_force'] - 1:+.1e} |"
            print(line, flush=True)


if __name__ == "__main__":
    main()
