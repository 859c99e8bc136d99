"""The same body as a finite-element and as a boundary-element body, side by
side: the founding paper's dissimilar two cubes (docs/validation.md, "The
paper's two cubes with one cube FEM") with the lower cube BEM (quad4, N
divisions per edge) or FEM (Q2 hexahedra, N per edge: the same boundary
resolution), the upper cube BEM (quad4, N - 1; E = 1e8), μ = 0.1, the top
moved 0.04 down, default SolverOptions.

Prints a Markdown table per N and model: the lower cube's unknowns (BEM:
3 per functional node; FEM: its volume dofs), the stages of
ContactProblem.solve as it times them, the whole solve's wall and CPU time,
the process's peak RSS, the normal force and its difference from the BEM
lower cube's.  Each (N, model) runs in its own process; with --repeat K the
times are medians over K runs and the RSS the largest.

    python benchmarks/fem_bem_two_cubes.py [--sizes 6,12,18] [--repeat 3]
"""

from __future__ import annotations

import argparse
import json
import resource
import sys
import time

from _common import machine_line, run_median

#: the times that are medians over the runs
TIMES = ("assembly_s", "condensation_s", "newton_s", "wall_s", "cpu_s")

MODELS = ("bem", "fem")


def one(n: int, model: str) -> dict:
    import bemcontact as bc

    fixed = {"zmin": bc.Displacement((0.0, 0.0, 0.0))}
    mat = bc.LinearElastic(1.0e4, 0.3)
    if model == "fem":
        from bemcontact.fem import FiniteElementBody, box_volume

        lower = FiniteElementBody(box_volume((0, 0, 0), (2, 2, 2), n, "hex8", 2), mat, fixed,
                                  name="lower")
        unknowns = lower.n_dofs
    else:
        lower = bc.ElasticBody(bc.box((0, 0, 0), (2, 2, 2), n, "quad4"), mat, fixed, name="lower")
        unknowns = 3 * lower.discretization.n_points
    upper = bc.ElasticBody(bc.box((0, 0, 2), (2, 2, 4), n - 1, "quad4"), bc.LinearElastic(1e8, 0.3),
                           {"zmax": bc.Displacement((0.0, 0.0, -0.04))}, name="upper")
    t0, c0 = time.perf_counter(), time.process_time()
    res = bc.ContactProblem(lower, upper, bc.ContactPair("zmax", "zmin", 0.1)).solve(
        bc.SolverOptions())
    t = res.timings
    return {"n": n, "model": model, "unknowns": unknowns, "assembly_s": t["assembly"],
            "condensation_s": t["condensation"], "newton_s": t["newton"],
            "wall_s": time.perf_counter() - t0, "cpu_s": time.process_time() - c0,
            "peak_rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
            "normal_force": float(res.normal_force), "converged": bool(res.converged)}


def main() -> None:
    if sys.argv[1:2] == ["--one"]:  # "N:model", from run_median
        n, model = sys.argv[2].split(":")
        print(json.dumps(one(int(n), model)))
        return
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", default="6,12,18")
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    print(machine_line())
    print(f"medians of {args.repeat} runs\n")
    print("| N | lower cube | unknowns | assembly s | condensation s | Newton s | wall s | CPU s "
          "| peak RSS MB | P (N) | P vs BEM |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for n in (int(s) for s in args.sizes.split(",")):
        ref = None
        for model in MODELS:
            r = run_median(__file__, f"{n}:{model}", args.repeat, TIMES)
            ref = r["normal_force"] if ref is None else ref
            print(f"| {n} | {model.upper()} | {r['unknowns']:,} | {r['assembly_s']:.2f} | "
                  f"{r['condensation_s']:.2f} | {r['newton_s']:.2f} | {r['wall_s']:.2f} | "
                  f"{r['cpu_s']:.2f} | {r['peak_rss_mb']:.0f} | {r['normal_force']:.2f} | "
                  f"{100 * (r['normal_force'] / ref - 1):+.3f} % |", flush=True)


if __name__ == "__main__":
    main()
