"""Every Python recipe the docs show a user (```python blocks that load a
problem file) runs as written and gives the command line's numbers."""

from __future__ import annotations

import contextlib
import io
import json
import pathlib
import re
import shutil

import pytest

from bemcontact.cli import main

ROOT = pathlib.Path(__file__).resolve().parents[1]
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
RECIPES = [
    (page.name, block)
    for page in PAGES
    for block in re.findall(r"```python\n(.*?)```", page.read_text(), flags=re.S)
    if "load_problem(" in block
]


def test_there_is_a_recipe():
    assert any(name == "problem-file.md" for name, _ in RECIPES)


@pytest.mark.parametrize("page, code", RECIPES, ids=[f"{p}:{i}" for i, (p, _) in enumerate(RECIPES)])
def test_recipe_gives_the_command_line_s_numbers(tmp_path, monkeypatch, page, code):
    shutil.copytree(ROOT / "examples", tmp_path / "examples")
    monkeypatch.chdir(tmp_path)
    problem = re.search(r'load_problem\("([^"]+)"\)', code).group(1)
    out = re.search(r'write\(result, "([^"]+)"\)', code).group(1)
    text = io.StringIO()
    with contextlib.redirect_stdout(text):
        exec(compile(code, f"{page} recipe", "exec"), {})
    assert main(["run", problem, "--out", "cli", "--quiet"]) == 0
    api = json.loads((tmp_path / out / "summary.json").read_text())
    cli = json.loads((tmp_path / "cli" / "summary.json").read_text())
    for key in ("normal_force", "tangential_force", "newton_iterations"):
        assert api[key] == pytest.approx(cli[key], rel=1e-12, abs=1e-12 * cli["normal_force"]), key
    assert f"normal force {cli['normal_force']:.6g}" in text.getvalue()
