"""Two-body contact benchmark: the founding paper's dissimilar two cubes
(validation.md, "The founding paper's two cubes") at N = 4, 8, 12, 16
quad4 divisions per cube edge.

Lower cube [0,2]^2 x [0,2], N x N x N quad4 elements, E1 = 1e4, nu = 0.3,
z = 0 face fixed.  Upper cube [0,2]^2 x [2,4], (N-1) x (N-1) x (N-1) quad4
elements, so the two interface meshes do NOT match (N x N lower faces against
(N-1) x (N-1) upper faces); E2 = 1e8, nu = 0.3, z = 4 face displaced by
(0, 0, -0.04).  Coulomb friction mu = 0.1, mortar frame (on the coarser, upper
surface), default SolverOptions (one load step, tolerance 1e-10).

Prints a Markdown table: N, functional nodes of both bodies, interface frame
nodes, the stages of ContactProblem.solve as it times them (assembly: H and G
of both bodies; condensation: LU of each body's system and the multi-RHS
solves for the unit contact tractions, plus forming the interface system;
frame: building the mortar contact frame; Newton: the generalized Newton
iterations and line search), Newton's share of the total, peak RSS MB of the
process, the normal force (bounds 800-1077 N from the uniaxial-stress and
confined-modulus limits) and the stick/slip/open counts at the frame nodes.

Each size runs in its own subprocess so the peak RSS is that size's; with
--repeat K each size runs K times (each in a fresh process) and every figure
in the table is the median over the K runs.
Usage:  python benchmarks/two_cubes_N4_16.py [--sizes 4,8,12,16] [--repeat 3]
"""

from __future__ import annotations

import argparse
import json
import resource
import statistics
import sys


def one(divisions: int) -> dict:
    import bemcontact as bc

    n = int(divisions)
    if n < 2:
        raise ValueError("divisions must be >= 2 (the upper cube has divisions - 1)")
    lower = bc.ElasticBody(
        bc.box((0, 0, 0), (2, 2, 2), n, "quad4"),
        bc.LinearElastic(1.0e4, 0.3),
        {"zmin": bc.Displacement((0.0, 0.0, 0.0))},
        name="lower",
    )
    upper = bc.ElasticBody(
        bc.box((0, 0, 2), (2, 2, 4), n - 1, "quad4"),
        bc.LinearElastic(1.0e8, 0.3),
        {"zmax": bc.Displacement((0.0, 0.0, -0.04))},
        name="upper",
    )
    problem = bc.ContactProblem(lower, upper, bc.ContactPair("zmax", "zmin", 0.1))
    res = problem.solve(bc.SolverOptions())
    t = res.timings
    counts = res.frame.counts()
    return {
        "divisions": n,
        "nodes": sum(len(b.points) for b in res.bodies),
        "nodes_lower": len(res.bodies[0].points),
        "nodes_upper": len(res.bodies[1].points),
        "frame_nodes": len(res.frame.points),
        "assembly_s": t["assembly"],
        "condensation_s": t["condensation"],
        "frame_s": t["frame"],
        "newton_s": t["newton"],
        "total_s": t["total"],
        "newton_iterations": int(res.newton_iterations),
        "converged": bool(res.converged),
        "peak_rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0,
        "normal_force": float(res.normal_force),
        "tangential_force": float(res.tangential_force),
        "stick": counts.get("stick", 0),
        "slip": counts.get("slip", 0),
        "open": counts.get("open", 0),
    }


def _median_row(runs: list[dict]) -> dict:
    row = dict(runs[0])
    for k, v in runs[0].items():
        if isinstance(v, float):
            row[k] = statistics.median(r[k] for r in runs)
    row["converged"] = all(r["converged"] for r in runs)
    return row


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--sizes", default="4,8,12,16", help="lower-cube divisions per edge (upper: one fewer)")
    p.add_argument("--repeat", type=int, default=1, help="runs per size (fresh process each); medians reported")
    p.add_argument("--one", type=int, help=argparse.SUPPRESS)
    a = p.parse_args()
    if a.one:
        print(json.dumps(one(a.one)))
        return
    from _common import machine_line, run_one

    rows = []
    for s in [int(x) for x in a.sizes.split(",")]:
        runs = [run_one(__file__, s) for _ in range(max(1, a.repeat))]
        rows.append(_median_row(runs))
        print(
            f"  done: N = {s}, {rows[-1]['nodes']} nodes, total {rows[-1]['total_s']:.2f} s",
            file=sys.stderr, flush=True,
        )
    rep = f", median of {a.repeat} runs per size" if a.repeat > 1 else ""
    print(machine_line(rep) + "\n")
    print(
        "| N | nodes | frame nodes | assembly s | condensation s | frame s | Newton it. | Newton s "
        "| Newton % | total s | peak RSS MB | normal force N | stick | slip | open |"
    )
    print("|---:" * 15 + "|")
    for r in rows:
        conv = "" if r["converged"] else " (not converged)"
        print(
            f"| {r['divisions']} | {r['nodes']} | {r['frame_nodes']} | {r['assembly_s']:.2f} "
            f"| {r['condensation_s']:.2f} | {r['frame_s']:.2f} | {r['newton_iterations']}{conv} "
            f"| {r['newton_s']:.2f} | {100.0 * r['newton_s'] / r['total_s']:.1f} | {r['total_s']:.2f} "
            f"| {r['peak_rss_mb']:.0f} | {r['normal_force']:.1f} | {r['stick']} | {r['slip']} | {r['open']} |"
        )


if __name__ == "__main__":
    main()
