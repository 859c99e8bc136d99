"""Packaging: the version is written once; builds are portable unless native
tuning is asked for; a wheel built from this checkout installs into a fresh
virtual environment with its declared dependencies only (no extras) and runs
the two-cube example there to the documented force, the figures skipped with
one warning line because matplotlib is not installed.

The wheel test takes minutes and downloads the dependencies from PyPI: it is
marked ``packaging`` (deselected by default, pyproject.toml) and ``slow``;
run it with ``make test-wheel`` (``pytest -m packaging tests/test_packaging.py``).
"""

from __future__ import annotations

import importlib.metadata
import json
import os
import pathlib
import re
import shutil
import subprocess
import sys
import tomllib
import zipfile

import pytest

import bemcontact

ROOT = pathlib.Path(__file__).resolve().parents[1]
VERSION = bemcontact.__version__
FIGURES_SKIPPED = (
    'bemcontact: warning: figures skipped (frame_tractions.png): matplotlib is not installed; '
    'pip install "bemcontact[plot]" to draw them'
)


def test_the_version_is_written_once():
    """pyproject.toml takes it from src/bemcontact/_version.py, and no other
    module assigns one; the installed metadata agrees."""
    pyproject = tomllib.loads((ROOT / "pyproject.toml").read_text())
    assert "version" not in pyproject["project"]
    assert "version" in pyproject["project"]["dynamic"]
    provider = pyproject["tool"]["scikit-build"]["metadata"]["version"]
    assert provider["input"] == "src/bemcontact/_version.py"
    assigned = [
        p.relative_to(ROOT).as_posix() for p in (ROOT / "src").rglob("*.py")
        if re.search(r"^\s*(__version__|VERSION)\s*=", p.read_text(), flags=re.MULTILINE)
    ]
    assert assigned == ["src/bemcontact/_version.py"]
    assert importlib.metadata.version("bemcontact") == VERSION


def test_native_tuning_is_an_opt_in():
    """CMake's default and every pip build are portable; `make install` opts
    in (NATIVE=ON, overridable), `make wheel` does not."""
    cmake = (ROOT / "CMakeLists.txt").read_text()
    assert re.search(r"option\(BEMCONTACT_NATIVE \"[^\"]*\" OFF\)", cmake)
    pyproject = tomllib.loads((ROOT / "pyproject.toml").read_text())
    assert pyproject["tool"]["scikit-build"]["cmake"]["define"]["BEMCONTACT_NATIVE"] == "OFF"
    make = shutil.which("make")
    if make is None:  # pragma: no cover - make is part of the documented set-up
        pytest.skip("make is not installed")

    def recipe(*args):
        r = subprocess.run([make, "-n", *args], cwd=ROOT,
                           capture_output=True, text=True, check=True)
        return r.stdout

    wheel = recipe("wheel")
    assert "pip wheel" in wheel and "cmake.define.BEMCONTACT_NATIVE=OFF" in wheel
    assert "cmake.define.BEMCONTACT_NATIVE=ON" in recipe("install")
    assert "cmake.define.BEMCONTACT_NATIVE=OFF" in recipe("install", "NATIVE=OFF")


def _run(argv, **kwargs) -> subprocess.CompletedProcess:
    r = subprocess.run([str(a) for a in argv], capture_output=True, text=True, check=False,
                       **kwargs)
    assert r.returncode == 0, f"{argv}: exit {r.returncode}\n{r.stdout}\n{r.stderr}"
    return r


# what the fresh environment reports about the installed package
PROBE = """\
import importlib.util, json, bemcontact, bemcontact._core as core
from bemcontact._native import build_info
print(json.dumps({**build_info(), "file": core.__file__, "version": bemcontact.__version__,
                  "missing": [m for m in ("gmsh", "matplotlib")
                              if importlib.util.find_spec(m) is None]}))
"""


@pytest.mark.slow
@pytest.mark.packaging
def test_wheel_is_portable_and_runs_in_a_fresh_venv_without_extras(tmp_path):
    env = {k: v for k, v in os.environ.items()
           if k not in ("PYTHONPATH", "VIRTUAL_ENV", "PYTHONHOME")}
    dist = tmp_path / "dist"
    # as `make wheel` does, with the defaults (no native define) and its own build directory
    _run([sys.executable, "-m", "pip", "wheel", "--quiet", "--no-build-isolation", "--no-deps",
          "--wheel-dir", dist, "--config-settings", f"build-dir={tmp_path / 'build'}", ROOT],
         cwd=tmp_path, env=env)
    (wheel,) = dist.glob("bemcontact-*.whl")
    assert wheel.name.startswith(f"bemcontact-{VERSION}-")
    with zipfile.ZipFile(wheel) as z:
        names = z.namelist()
        metadata = z.read(f"bemcontact-{VERSION}.dist-info/METADATA").decode()
    assert [n for n in names if re.fullmatch(r"bemcontact/_core\..*\.so", n)], names
    assert f"\nVersion: {VERSION}\n" in metadata
    assert "Provides-Extra: gmsh" in metadata and "Provides-Extra: plot" in metadata

    venv = tmp_path / "venv"
    _run([sys.executable, "-m", "venv", venv], env=env)
    bindir = venv / "bin"
    _run([bindir / "python", "-m", "pip", "install", "--quiet", wheel], cwd=tmp_path, env=env)
    info = json.loads(_run([bindir / "python", "-c", PROBE], cwd=tmp_path, env=env).stdout)
    assert info["native"] is False and "-march" not in info["flags"], info
    assert info["file"].startswith(str(venv)) and info["version"] == VERSION
    assert info["missing"] == ["gmsh", "matplotlib"]  # the extras are not installed
    if shutil.which("objdump"):
        # the baseline x86-64 set has no AVX: no 256/512-bit registers anywhere
        asm = _run(["objdump", "-d", "--no-show-raw-insn", info["file"]]).stdout
        assert len(asm) > 100_000
        wide = [line for line in asm.splitlines() if "%ymm" in line or "%zmm" in line]
        assert wide == [], wide[:5]

    exe = bindir / "bemcontact"
    assert _run([exe, "--version"], env=env).stdout.strip() == f"bemcontact {VERSION}"
    example = ROOT / "examples" / "two_cubes_dissimilar.toml"
    r = _run([exe, "check", example], cwd=tmp_path, env=env)
    assert r.stderr.splitlines() == [FIGURES_SKIPPED] and ": valid" in r.stdout
    out = tmp_path / "out"
    r = _run([exe, "run", example, "--out", out, "--threads", "1"], cwd=tmp_path, env=env)
    assert r.stderr.splitlines() == [FIGURES_SKIPPED]
    assert "normal force      834.137 N" in r.stdout  # docs/getting-started.md
    for name in ("summary.json", "frame.pvd", "frame.vtu", "lower.vtu", "frame.csv",
                 "lower_interface.csv", "upper_interface.csv"):
        assert (out / name).is_file(), name
    assert not (out / "frame_tractions.png").exists()
    assert json.loads((out / "summary.json").read_text())["version"] == VERSION
    # a gmsh-generated mesh without gmsh: one line naming the install command
    hertz = ROOT / "examples" / "hertz_sphere_on_block.toml"
    r = subprocess.run([exe, "check", hertz], capture_output=True, text=True, env=env, check=False)
    assert r.returncode == 2 and len(r.stderr.splitlines()) == 1, r.stderr
    assert 'pip install "bemcontact[gmsh]"' in r.stderr
