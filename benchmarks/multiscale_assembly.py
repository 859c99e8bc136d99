"""An assembly on the contact grid against its pairs alone and the full path:
examples/two_indenters_multiscale.toml (two steel hemispheres 4 mm apart
pressed 0.03 and 0.02 mm into one block in 4 increments, μ = 0.3).

    python benchmarks/multiscale_assembly.py [--repeat 3] [--json FILE]

Rows, each in its own process (its peak RSS):

* ``assembly``: the example as ``bemcontact run`` solves and writes it
  (ProblemFile.solve and .write: one grid per pair, the coupling, every
  file), the median of ``--repeat`` runs;
* ``pairs alone``: each pair solved on its own grid in turn, no coupling
  (what the coupling costs on top);
* ``full path``: the same bodies meshed at h = 0.11 (a/h = 5) near both
  contacts, once (about a minute: it is what the grid saves).

The forces are printed with the times: the accuracy is docs/validation.md's
("Assemblies on the grid")."""

from __future__ import annotations

import argparse
import json
import os
import pathlib
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from _common import machine_line, run_median, run_one  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "examples" / "two_indenters_multiscale.toml"


def _assembly() -> dict:
    import bemcontact as bc

    problem = bc.load_problem(EXAMPLE)
    result = problem.solve()
    with tempfile.TemporaryDirectory() as tmp:
        problem.write(result, pathlib.Path(tmp) / "run")
    return {"forces": [float(r.history[-1].force[2]) for r in result.pairs],
            "sweeps": len(result.sweeps), "timings": result.timings}


def _alone() -> dict:
    import bemcontact as bc
    from bemcontact.contact import ContactPair, ContactProblem, LoadStep
    from bemcontact.multiscale.pair import GridOptions, solve_on_grid

    problem = bc.load_problem(EXAMPLE, check_overlap=False).contact_problem()
    forces = []
    for k, pair in enumerate(problem.pairs):
        a, b = problem.links[k]
        alone = ContactProblem(problem.bodies[a], problem.bodies[b],
                               ContactPair(pair.surface1, pair.surface2,
                                           pair.friction_coefficient))
        res = solve_on_grid(alone, [LoadStep(increments=4)], GridOptions(grid_size=0.05))
        forces.append(float(res.history[-1].force[2]))
    return {"forces": forces}


def _full() -> dict:
    from bemcontact.contact import SolverOptions
    from bemcontact.validation.assemblies import two_indenters_on_block

    problem = two_indenters_on_block(0.11)
    res = problem.solve(SolverOptions(load_steps=4))
    return {"forces": [float(p.normal_force) for p in res.pairs],
            "nodes": sum(int(b.discretization.n_points) for b in problem.bodies)}


def one(kind: str) -> dict:
    from bemcontact.bench import peak_rss_mb

    w, c = time.perf_counter(), time.process_time()
    row = {"assembly": _assembly, "alone": _alone, "full": _full}[kind]()
    return {"kind": kind, **row, "wall_s": time.perf_counter() - w,
            "cpu_s": time.process_time() - c, "peak_rss_mb": peak_rss_mb()}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--json", type=pathlib.Path)
    ap.add_argument("--skip-full", action="store_true", help="leave out the full path's row")
    ap.add_argument("--one", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.one is not None:
        print(json.dumps(one(args.one), default=float))
        return 0
    print(machine_line())
    script = os.path.abspath(__file__)
    rows = [run_median(script, "assembly", args.repeat), run_median(script, "alone", args.repeat)]
    if not args.skip_full:
        rows.append(run_one(script, "full"))
    print(f"{'row':>10} {'wall s':>8} {'CPU s':>8} {'RSS MB':>8}  normal forces (N)")
    for row in rows:
        print(f"{row['kind']:>10} {row['wall_s']:8.2f} {row['cpu_s']:8.2f} "
              f"{row['peak_rss_mb']:8.0f}  " + ", ".join(f"{f:.2f}" for f in row["forces"])
              + (f"  ({row['sweeps']} sweeps; {row['timings']})" if "sweeps" in row else ""))
    if args.json:
        args.json.write_text(json.dumps(rows, indent=1, default=float))
    return 0


if __name__ == "__main__":
    sys.exit(main())
