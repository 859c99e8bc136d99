"""Every command the README and the docs show a user (lines starting with
``$ `` in ```console blocks) runs and does what the docs say: a new user
following them gets from a clone to ParaView files and a PNG.

``make`` lines are the README's set-up commands: ``make test`` is this suite
and ``make demo``/``make docs`` are run by CI-equivalent tests elsewhere
(tests/test_examples.py, tests/test_docs.py), so for them only the target's
existence is checked (``make -n``).  Output directories (``out/...``) are
redirected into a temporary directory so the checkout is not written to.
"""

from __future__ import annotations

import json
import pathlib
import re
import shlex
import subprocess
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[1]
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
BIN = pathlib.Path(sys.executable).parent


def documented_commands() -> list[tuple[str, str]]:
    out = []
    for page in PAGES:
        text = page.read_text()
        for block in re.findall(r"```console\n(.*?)```", text, flags=re.S):
            for line in block.splitlines():
                if line.startswith("$ "):
                    out.append((page.name, line[2:].strip()))
    return out


COMMANDS = documented_commands()


def test_the_docs_show_the_whole_path():
    """The getting-started path is documented: set-up, check, run, mesh-info."""
    shown = " | ".join(c for _, c in COMMANDS)
    for needed in ("make demo", "bemcontact check", "bemcontact run", "bemcontact mesh-info"):
        assert needed in shown, needed
    assert len(COMMANDS) >= 6


def _argv(command: str, tmp: pathlib.Path) -> list[str]:
    argv = shlex.split(command, comments=True)
    if argv[0].startswith(".venv/bin/"):
        argv[0] = str(BIN / argv[0].removeprefix(".venv/bin/"))
    elif argv[0] in ("python", "python3"):
        argv[0] = sys.executable
    return [str(tmp / a) if a.startswith("out/") else a for a in argv]


@pytest.mark.parametrize("page, command", COMMANDS, ids=[c for _, c in COMMANDS])
def test_documented_command_runs(page, command, tmp_path):
    argv = _argv(command, tmp_path)
    if argv[0] == "make":
        r = subprocess.run(["make", "-n", *argv[1:]], cwd=ROOT, capture_output=True, text=True)
        assert r.returncode == 0, f"{page}: {command}: {r.stderr}"
        return
    r = subprocess.run(argv, cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, f"{page}: {command}:\n{r.stdout}\n{r.stderr}"
    assert "Traceback" not in r.stderr
    if "run" in argv[1:2]:
        out = pathlib.Path(argv[argv.index("--out") + 1])
        # what getting-started.md promises: ParaView collections, VTU, a PNG, the
        # summary; on the contact grid (method = "multiscale") the grid's files
        summary = json.loads((out / "summary.json").read_text())
        used = summary.get("method", {})
        if isinstance(used, dict) and used.get("used") == "multiscale":
            # an assembly: each pair's grid files under its stem
            stems = [f"{p['files']}_" for p in summary.get("pairs", [])] or [""]
            names = tuple(f"{s}{n}" for s in stems
                          for n in ("grid.vtu", "grid_tractions.png", "grid.csv"))
            figure = f"{stems[0]}grid_tractions.png"
        else:
            names = ("frame.pvd", "frame.vtu", "frame_tractions.png", "frame.csv")
            figure = "frame_tractions.png"
        for name in ("summary.json", *names):
            assert (out / name).is_file(), name
        assert (out / figure).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
        assert "converged" in r.stdout


def test_getting_started_numbers_are_what_the_commands_print(tmp_path):
    """getting-started.md quotes the dissimilar cubes' normal force."""
    text = (ROOT / "docs" / "getting-started.md").read_text()
    assert "834.137 N" in text
    r = subprocess.run(
        [str(BIN / "bemcontact"), "run", "examples/two_cubes_dissimilar.toml", "--out",
         str(tmp_path / "o")], cwd=ROOT, capture_output=True, text=True, check=True,
    )
    assert "normal force      834.137 N" in r.stdout
