"""Assembly benchmark: the three-body problem of
examples/thrust_bearing_ball.toml (a ball between two washers, two contact
pairs) against its two two-body parts solved separately with the same meshes:
``lower``/``ball`` (the ball's top cap pushed down by half the approach) and
``ball``/``upper`` (the ball's bottom cap held, the upper washer pushed down by
half the approach), the ball held by its cage band in both.

The assembly condenses each body once (the ball on both pairs' traction
modes at once: one LU, the two pairs' right-hand sides) and runs one Newton
on both frames; the parts condense the ball twice.  Times are those
``ContactProblem.solve`` reports (frame, assembly, condensation, Newton,
total), meshing excluded; peak RSS of the process.  Each case runs in a fresh
process; with --repeat K every figure is the median of K runs.

Usage:  python benchmarks/assembly_ball_N3.py [--repeat 3]
"""

from __future__ import annotations

import argparse
import json
import pathlib
import resource
import statistics
import subprocess
import sys

EXAMPLE = pathlib.Path(__file__).resolve().parents[1] / "examples" / "thrust_bearing_ball.toml"
CASES = ("assembly", "lower+ball", "ball+upper")


def problem(case: str):
    """The ContactProblem of ``case`` built on the example's meshes."""
    import bemcontact as bc
    from bemcontact.problemfile import load_problem

    pf = load_problem(EXAMPLE, check_overlap=False)
    if case == "assembly":
        return pf.contact_problem()
    lower, ball, upper = pf.bodies
    half = -0.015
    cage = {"band": bc.Displacement((0.0, 0.0, None))}
    if case == "lower+ball":
        b = bc.ElasticBody(ball.mesh, ball.material,
                           {**cage, "top": bc.Displacement((0.0, 0.0, half))}, name="ball")
        return bc.ContactProblem(lower, b, pf.pairs[0])
    b = bc.ElasticBody(ball.mesh, ball.material, {**cage, "bottom": bc.Fixed()}, name="ball")
    u = bc.ElasticBody(upper.mesh, upper.material,
                       {"zmax": bc.Displacement((0.0, 0.0, half))}, name="upper")
    return bc.ContactProblem(b, u, pf.pairs[1])


def one(case: str) -> dict:
    prob = problem(case)
    res = prob.solve()
    row = {k: float(v) for k, v in res.timings.items()}
    row.update(case=case, converged=bool(res.converged),
               newton_iterations=int(res.newton_iterations),
               frame_nodes=int(sum(int(p.frame.weights.astype(bool).sum()) for p in res.pairs)),
               forces=[float(p.normal_force) for p in res.pairs],
               peak_rss_mb=resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0)
    return row


def main() -> None:
    sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
    from _common import machine_line

    ap = argparse.ArgumentParser()
    ap.add_argument("--one", choices=CASES)
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    if args.one:
        print(json.dumps(one(args.one)))
        return
    rows = {}
    for case in CASES:
        runs = []
        for _ in range(args.repeat):
            out = subprocess.run([sys.executable, __file__, "--one", case], capture_output=True,
                                 text=True, check=True).stdout
            runs.append(json.loads(out.strip().splitlines()[-1]))
        rows[case] = {k: statistics.median(r[k] for r in runs)
                      for k in ("frame", "assembly", "condensation", "newton", "total",
                                "peak_rss_mb")}
        rows[case].update({k: runs[0][k] for k in ("newton_iterations", "frame_nodes", "forces")})
    print(machine_line(f", medians of {args.repeat} runs"))
    print()
    print("| case | frame nodes | Newton its | frame s | assembly s | condensation s | "
          "Newton s | total s | peak RSS MB | normal forces N |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for case, r in rows.items():
        print(f"| {case} | {r['frame_nodes']} | {r['newton_iterations']} | {r['frame']:.2f} | "
              f"{r['assembly']:.2f} | {r['condensation']:.2f} | {r['newton']:.2f} | "
              f"{r['total']:.2f} | {r['peak_rss_mb']:.0f} | "
              + ", ".join(f"{f:.1f}" for f in r["forces"]) + " |")
    parts = rows["lower+ball"]["total"] + rows["ball+upper"]["total"]
    print()
    print(f"assembly {rows['assembly']['total']:.2f} s against the parts' sum {parts:.2f} s "
          f"({rows['assembly']['total'] / parts:.2f})")


if __name__ == "__main__":
    main()
