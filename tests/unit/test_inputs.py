"""Hostile input files: FIFOs and devices, oversized files, a
byte-order mark, deep nesting, Ctrl-C and a closed pipe: one line, the right
exit code, never a hang or a traceback."""

from __future__ import annotations

import os
import subprocess
import sys

import pytest

import bemcontact as bc
from bemcontact.cli import main
from bemcontact.inputs import check_regular_file

from .test_cli import TINY, problem


def _one_line(capsys, code, expected_code, *needles):
    err = capsys.readouterr().err
    assert code == expected_code, err
    assert err.count("\n") == 1, err
    for n in needles:
        assert n in err, err
    return err


def test_fifo_problem_file_is_refused_not_read(tmp_path, capsys):
    fifo = tmp_path / "problem.toml"
    os.mkfifo(fifo)  # opening it for reading would block forever
    code = main(["check", str(fifo)])
    _one_line(capsys, code, 2, "problem.toml: is not a regular file (a FIFO, socket or device)")


@pytest.mark.parametrize("command", ["check", "run"])
def test_device_problem_file(tmp_path, capsys, command):
    argv = [command, "/dev/zero"] + (["--out", str(tmp_path / "o")] if command == "run" else [])
    _one_line(capsys, main(argv), 2, "/dev/zero: is not a regular file")
    assert list(tmp_path.iterdir()) == []


def test_device_and_fifo_as_mesh_file(tmp_path, capsys):
    fifo = tmp_path / "cube.msh"
    os.mkfifo(fifo)
    for mesh in ("/dev/zero", str(fifo)):
        src = tmp_path / "p.toml"
        text = TINY.format(E="1e4", top='[0, 0, -0.04]', mu="0").replace(
            'mesh = { box = { lower = [0, 0, 0], upper = [2, 2, 2], divisions = 1 } }',
            f'mesh = {{ file = "{mesh}" }}', 1)
        assert mesh in text
        src.write_text(text)
        _one_line(capsys, main(["check", str(src)]), 2, "body[0].mesh.file", "not a regular file")
    with pytest.raises(bc.MeshError, match="not a regular file"):
        bc.read_mesh(fifo)


def test_size_limit_before_reading(tmp_path):
    big = tmp_path / "big.toml"
    with open(big, "wb") as f:  # sparse: 20 GB that take no room
        f.truncate(20 * 10**9)
    with pytest.raises(bc.ConfigError, match=r"big.toml: 20,000 MB is too large for a problem file"):
        bc.load_problem(big)
    with pytest.raises(bc.ConfigError, match="too large"):
        check_regular_file(big, "mesh file", 10**6)


def test_byte_order_mark_is_accepted(tmp_path):
    src = problem(tmp_path)
    src.write_bytes(b"\xef\xbb\xbf" + src.read_bytes())
    (tmp_path / "plain").mkdir()
    plain = bc.load_problem(problem(tmp_path / "plain"))
    assert bc.load_problem(src).units == plain.units == {"length": "mm", "force": "N", "stress": "MPa"}


def test_deep_nesting_is_one_line(tmp_path, capsys):
    deep = tmp_path / "deep.toml"
    deep.write_text("x = " + "[" * 5000 + "]" * 5000 + "\n")
    _one_line(capsys, main(["check", str(deep)]), 2, "deep.toml: ")


def test_ctrl_c_during_the_solve_is_one_line_and_leaves_the_output(tmp_path, capsys, monkeypatch):
    out = tmp_path / "out"
    src = problem(tmp_path)
    assert main(["run", str(src), "--out", str(out), "--quiet"]) == 0
    before = {p: p.read_bytes() for p in out.rglob("*") if p.is_file()}

    def interrupt(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(bc.ProblemFile, "solve", interrupt)
    _one_line(capsys, main(["run", str(src), "--out", str(out)]), 130, "bemcontact: interrupted")
    assert {p: p.read_bytes() for p in out.rglob("*") if p.is_file()} == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out", "tiny.toml"]  # no lock left


def test_closed_pipe_is_quiet(tmp_path):
    """`bemcontact check problem.toml | head -1` (a real pipe, closed early)."""
    src = problem(tmp_path)
    proc = subprocess.run(
        f"{sys.executable} -m bemcontact check {src} | head -c 1",
        shell=True, capture_output=True, text=True, timeout=120,
    )
    assert "Traceback" not in proc.stderr and "BrokenPipe" not in proc.stderr, proc.stderr


def test_symbolic_link_loops_and_dangling_links(tmp_path, capsys):
    """A loop of links is named as such (mesh-info said "no such file")."""
    (tmp_path / "a.msh").symlink_to("b.msh")
    (tmp_path / "b.msh").symlink_to("a.msh")
    (tmp_path / "gone.msh").symlink_to("nothing.msh")
    _one_line(capsys, main(["mesh-info", str(tmp_path / "a.msh")]), 2,
              "a.msh: cannot read the mesh file: Too many levels of symbolic links")
    _one_line(capsys, main(["mesh-info", str(tmp_path / "gone.msh")]), 2,
              "gone.msh: cannot read the mesh file: no such file")
    _one_line(capsys, main(["check", str(tmp_path / "a.msh")]), 2,
              "a.msh: cannot read the problem file: Too many levels of symbolic links")
