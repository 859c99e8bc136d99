"""A [[step]]'s rolling table through `bemcontact run`: bad input is one
line naming the field, exit 2, and nothing written."""

from __future__ import annotations

import pathlib
import subprocess
import sys

import pytest

EXAMPLE = pathlib.Path(__file__).parents[3] / "examples" / "rolling_ball_multiscale.toml"
ROLLING = ('rolling = { direction = [1, 0, 0], creepage = [-0.0005, 0.0], spin = 0.0, '
           'mode = "steady", speed = 1000.0 }')


def run(tmp_path, text):
    src = EXAMPLE.read_text()
    assert ROLLING in src
    path = tmp_path / "p.toml"
    path.write_text(src.replace(ROLLING, text) if text.startswith("rolling") else
                    src.replace("friction_coefficient = 0.3", text))
    out = tmp_path / "out"
    proc = subprocess.run([sys.executable, "-m", "bemcontact", "run", str(path), "--out",
                           str(out), "--quiet"], capture_output=True, text=True)
    return proc, out


@pytest.mark.parametrize("text, says", [
    ('rolling = { direction = [1, 0, 0.5] }', "step[1].rolling.direction"),
    ('rolling = { direction = [1, 0, 0], mode = "transient" }', "step[1].rolling.distance"),
    ('rolling = { direction = [1, 0, 0], distance = 0.01 }', "step[1].rolling.distance"),
    ('rolling = { direction = [1, 0, 0], creepage = [1, 2, 3] }', "step[1].rolling.creepage"),
    ('rolling = { direction = [1, 0, 0], mode = "stedy" }', "step[1].rolling.mode"),
    ('friction_coefficient = 0.0', "frictionless"),
])
def test_bad_rolling_input_is_one_line_exit_2_nothing_written(tmp_path, text, says):
    proc, out = run(tmp_path, text)
    assert proc.returncode == 2, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and says in lines[0], proc.stderr
    assert "Traceback" not in proc.stderr
    assert not out.exists()


def test_check_lists_the_rolling_steps(tmp_path):
    proc = subprocess.run([sys.executable, "-m", "bemcontact", "check", str(EXAMPLE)],
                          capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    assert ("rolling: step[1] (rolling) steady along [1.0, 0.0, 0.0], creepage [-0.0005, 0.0], "
            "spin 0") in proc.stdout


@pytest.mark.parametrize("changes, says", [
    ({"friction_coefficient = 0.3": "friction_coefficient = 0.0"}, "step[1].rolling: a frictionless"),
    ({ROLLING: 'rolling = { direction = [0, 0.6, 0.8] }'}, "step[1].rolling.direction"),
])
def test_the_full_path_refuses_bad_rolling_before_it_solves(tmp_path, changes, says):
    """method = "full": the same one-line refusals, before any body is
    condensed (the run stops within seconds) and nothing written."""
    src = EXAMPLE.read_text().replace('method = "multiscale"', 'method = "full"')
    for old, new in changes.items():
        assert old in src
        src = src.replace(old, new)
    path = tmp_path / "p.toml"
    path.write_text(src)
    out = tmp_path / "out"
    proc = subprocess.run([sys.executable, "-m", "bemcontact", "run", str(path), "--out",
                           str(out), "--quiet"], capture_output=True, text=True)
    assert proc.returncode == 2, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and says in lines[0], proc.stderr
    assert not out.exists()
