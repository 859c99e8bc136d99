"""A sweep against separate runs: wall time of ``bemcontact sweep``
over 8 points against 8 ``bemcontact run`` of the same points, one after the
other, the largest difference of the key outputs (which must be below
1e-10 relative), and whether every point's directory holds the files of its
separate run (the same work per point: VTU, CSV, summary and the
frame_tractions.png figure).

Cases:
  friction  examples/two_cubes_dissimilar.toml, contact.friction_coefficient
            = 0.05 ... 0.4 (8 values): only the friction changes, so the sweep
            condenses the bodies once per worker and re-solves.
  load      examples/hertz_sphere_on_block.toml, the sphere's base pushed down
            0.005 ... 0.04 mm (8 values): only a load value changes.

    python benchmarks/sweep_points8.py [--case friction|load|both] [--workers N]

prints a Markdown table (case | points | separate runs s | sweep s | speed-up |
largest relative difference | same files) under the machine line.  Time it on a quiet
machine only: the sweep uses every core.  ``--problem FILE --key KEY
--values V1,V2,...`` runs another study (the smoke test uses a tiny one).
"""

from __future__ import annotations

import argparse
import csv
import json
import os
import pathlib
import shutil
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from _common import machine_line  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[1]
BIN = pathlib.Path(sys.executable).parent / "bemcontact"
CASES = {
    "friction": ("examples/two_cubes_dissimilar.toml", "contact.friction_coefficient",
                 [0.05, 0.1, 0.15, 0.2, 0.25, 0.3, 0.35, 0.4]),
    "load": ("examples/hertz_sphere_on_block.toml",
             "body[1].boundary_conditions.base.displacement[2]",
             [-0.005, -0.01, -0.015, -0.02, -0.025, -0.03, -0.035, -0.04]),
}
#: Outputs compared between the sweep's table and the runs' summary.json.
COMPARED = ("normal_force", "tangential_force")


def _point_files(problem: pathlib.Path, key: str, values, directory: pathlib.Path):
    """The points' problem files, as the sweep writes them (its own
    planner), so both sides solve exactly the same problems."""
    from bemcontact.study.sweep import plan_sweep

    plan = plan_sweep(problem, directory / "unused", [f"{key}={','.join(map(str, values))}"])
    files = []
    for point in plan.points:
        f = directory / f"{point.name}.toml"
        f.write_text(point.text, encoding="utf-8")
        files.append(f)
    return files


def _files(directory: pathlib.Path) -> set[str]:
    return {str(f.relative_to(directory)) for f in directory.rglob("*") if f.is_file()}


def separate(problem: pathlib.Path, key: str, values, tmp: pathlib.Path) -> tuple[float, list]:
    """8 ``bemcontact run`` of the points, one after the other: seconds and
    each summary.json with the run's file names (the point files are made
    first, not timed)."""
    files = _point_files(problem, key, values, tmp)
    t0 = time.perf_counter()
    for k, f in enumerate(files):
        subprocess.run([str(BIN), "run", str(f), "--out", str(tmp / f"run_{k}"), "--quiet"],
                       check=True, cwd=ROOT)
    seconds = time.perf_counter() - t0
    return seconds, [{**json.loads((tmp / f"run_{k}" / "summary.json").read_text()),
                      "files": _files(tmp / f"run_{k}")} for k in range(len(files))]


def sweep(problem: pathlib.Path, key: str, values, tmp: pathlib.Path,
          workers: int | None) -> tuple[float, list[dict]]:
    """One ``bemcontact sweep`` of the points (a fresh local cluster, cache
    empty): seconds and the table's rows, each with its directory's file
    names."""
    out = tmp / "sweep"
    argv = [str(BIN), "sweep", str(problem), "--vary", f"{key}={','.join(map(str, values))}",
            "--out", str(out), "--quiet"]
    if workers:
        argv += ["--workers", str(workers)]
    t0 = time.perf_counter()
    subprocess.run(argv, check=True, cwd=ROOT)
    seconds = time.perf_counter() - t0
    with open(out / "table.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    for r in rows:
        r["files"] = _files(out / r["directory"])
    return seconds, rows


def one(problem, key: str, values, workers: int | None = None) -> dict:
    """The record of one case."""
    problem = (ROOT / problem).resolve()
    tmp = pathlib.Path(tempfile.mkdtemp(prefix="bemcontact-sweep-bench-"))
    try:
        t_sep, runs = separate(problem, key, values, tmp)
        t_sw, rows = sweep(problem, key, values, tmp, workers)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    diff = 0.0
    same = all(run["files"] == row["files"] for run, row in zip(runs, rows, strict=True))
    for run, row in zip(runs, rows, strict=True):
        scale = abs(run["normal_force"])
        for k in COMPARED:
            diff = max(diff, abs(float(row[k]) - run[k]) / scale)
    return {"problem": str(problem.relative_to(ROOT)) if problem.is_relative_to(ROOT)
            else str(problem), "key": key, "points": len(values), "separate_s": t_sep,
            "sweep_s": t_sw, "speedup": t_sep / t_sw, "max_rel_diff": diff,
            "all_ok": all(r["status"] == "ok" for r in rows), "same_files": same}


def main(argv=None) -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--case", choices=("friction", "load", "both"), default="both")
    p.add_argument("--workers", type=int, default=None)
    p.add_argument("--problem")
    p.add_argument("--key")
    p.add_argument("--values")
    args = p.parse_args(argv)
    if args.problem:
        cases = {"custom": (args.problem, args.key,
                            [float(v) for v in args.values.split(",")])}
    else:
        cases = {k: v for k, v in CASES.items() if args.case in (k, "both")}
    print(machine_line())
    print()
    print("| case | points | separate runs s | sweep s | speed-up | largest rel. difference "
          "| same files |")
    print("|---|---|---|---|---|---|---|")
    for name, (problem, key, values) in cases.items():
        r = one(problem, key, values, args.workers)
        print(f"| {name} | {r['points']} | {r['separate_s']:.1f} | {r['sweep_s']:.1f} | "
              f"{r['speedup']:.1f}x | {r['max_rel_diff']:.1e} | "
              f"{'yes' if r['same_files'] else 'NO'} |")
        print(json.dumps(r), file=sys.stderr)


if __name__ == "__main__":
    main()
