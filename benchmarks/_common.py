"""Shared by the benchmark scripts: run one size in a fresh process, time a
call's median in this one, and the machine / commit line printed above each
table."""

from __future__ import annotations

import json
import os
import platform
import statistics
import subprocess
import sys
import time


def run_one(script: str, size) -> dict:
    """``python SCRIPT --one SIZE`` in its own process (so the peak RSS is
    that size's); the last stdout line is the row as JSON."""
    out = subprocess.run(
        [sys.executable, script, "--one", str(size)], capture_output=True, text=True, check=True
    ).stdout
    return json.loads(out.strip().splitlines()[-1])


def run_median(script: str, size, repeat: int, keys=("cpu_s", "wall_s")) -> dict:
    """``run_one`` ``repeat`` times: the first run's row with the median of
    each of ``keys`` (each run's in ``<key>_runs``) and the largest
    ``peak_rss_mb``."""
    rows = [run_one(script, size) for _ in range(repeat)]
    row = dict(rows[0])
    for key in keys:
        row[key] = statistics.median(x[key] for x in rows)
        row[key + "_runs"] = [x[key] for x in rows]
    row["peak_rss_mb"] = max(x["peak_rss_mb"] for x in rows)
    return row


def timed(fn, repeat: int):
    """``fn()`` called ``repeat`` times in this process: (median wall s,
    median CPU s of this process, the last call's result)."""
    walls, cpus, out = [], [], None
    for _ in range(repeat):
        w, c = time.perf_counter(), time.process_time()
        out = fn()
        walls.append(time.perf_counter() - w)
        cpus.append(time.process_time() - c)
    return statistics.median(walls), statistics.median(cpus), out


def machine_line(extra: str = "") -> str:
    """``commit <sha>, <n> cores (<cpu>), Python <version><extra>``."""
    try:
        commit = subprocess.run(
            ["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True,
            cwd=os.path.dirname(os.path.abspath(__file__)),
        ).stdout.strip() or "unknown"
    except OSError:
        commit = "unknown"
    cpu = platform.processor() or platform.machine()
    return f"commit {commit}, {os.cpu_count()} cores ({cpu}), Python {platform.python_version()}{extra}"
