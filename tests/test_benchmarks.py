"""Smoke run of the benchmark scripts so they cannot rot (no timings asserted)."""

from __future__ import annotations

import importlib.util
import pathlib

BENCH = pathlib.Path(__file__).resolve().parents[1] / "benchmarks"


def test_one_body_benchmark_smoke():
    spec = importlib.util.spec_from_file_location("b", BENCH / "bem_one_body_N500_5000.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    row = mod.one(3)
    assert row["nodes"] == 144
    # the benchmark's problem has an exact (linear) solution: the error is
    # quadrature-level, as in the uniform-stress validation (1e-8)
    assert row["error"] < 1e-8
    assert row["assembly_s_2t"] > 0 and row["peak_rss_mb"] > 0
