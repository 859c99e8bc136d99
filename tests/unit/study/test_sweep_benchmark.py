"""Smoke run of benchmarks/sweep_points8.py on a tiny study (no timing
asserted): the sweep's points equal the separate runs."""

from __future__ import annotations

import importlib.util
import pathlib

from .conftest import tiny_problem

BENCH = pathlib.Path(__file__).resolve().parents[3] / "benchmarks" / "sweep_points8.py"


def test_sweep_benchmark_smoke(tmp_path):
    spec = importlib.util.spec_from_file_location("sweep_bench", BENCH)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    r = mod.one(tiny_problem(tmp_path), "contact.friction_coefficient", [0.01], workers=1)
    assert r["points"] == 1 and r["all_ok"]
    assert r["max_rel_diff"] <= 1e-10
    assert r["same_files"]  # each point's directory as its separate run's
    assert r["separate_s"] > 0 and r["sweep_s"] > 0
    assert set(mod.CASES) == {"friction", "load"} and len(mod.CASES["friction"][2]) == 8
