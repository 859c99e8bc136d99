"""Examples are tests: each asserts its key number."""

from __future__ import annotations

import importlib.util
import pathlib
import subprocess
import sys

import pytest

EXAMPLES = pathlib.Path(__file__).resolve().parents[1] / "examples"


def load(name):
    spec = importlib.util.spec_from_file_location(name, EXAMPLES / f"{name}.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


@pytest.mark.parametrize("element_type", ["quad4", "quad8"])
def test_compress_cube_reaction_equals_EA_strain(element_type):
    """Uniaxial compression is a uniform-stress state, which the elements
    represent exactly: the reaction must equal E A delta / L = 400 N to
    quadrature precision (1e-8, the uniform-stress tolerance)."""
    r = load("compress_cube").run(divisions=2, element_type=element_type)
    assert r["exact_N"] == 400.0
    assert r["reaction_N"] == pytest.approx(400.0, rel=1e-8)


def test_compress_cube_script_prints_the_comparison():
    out = subprocess.run(
        [sys.executable, str(EXAMPLES / "compress_cube.py")], capture_output=True, text=True,
        check=True,
    ).stdout
    assert "reaction on top face 400" in out and "E * A * strain" in out
