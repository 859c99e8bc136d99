"""The output directory rules (bemcontact.output.rundir): what is refused,
the lock, the whole-run swap and its recovery after a kill."""

from __future__ import annotations

import json
import os
import pathlib
import subprocess
import sys

import pytest

import bemcontact as bc
from bemcontact.output.rundir import MARKER, RunDirectory


def _run(path, files=("summary.json", "sub/a.txt"), **kw):
    with RunDirectory(path, **kw) as rd, rd.staging() as tmp:
        for f in files:
            (tmp / f).parent.mkdir(parents=True, exist_ok=True)
            (tmp / f).write_text(f)


@pytest.mark.parametrize("where, message", [
    ("", "empty path"),
    (".", "is the current directory"),
    ("/", "is a filesystem root"),
])
def test_refused_places(tmp_path, monkeypatch, where, message):
    monkeypatch.chdir(tmp_path)
    with pytest.raises(bc.ConfigError, match=message):
        RunDirectory(where)
    assert list(tmp_path.iterdir()) == []


def test_new_then_own_directory(tmp_path):
    out = tmp_path / "out"
    _run(out)
    manifest = json.loads((out / MARKER).read_text())
    assert manifest["files"] == ["sub/a.txt", "summary.json"]
    assert manifest["bemcontact"] == bc.__version__
    _run(out, files=("summary.json",))  # the earlier run's sub/a.txt was ours: replaced whole
    assert sorted(p.relative_to(out).as_posix() for p in out.rglob("*")) == [MARKER, "summary.json"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"]


def test_empty_existing_directory_is_accepted(tmp_path):
    (tmp_path / "out").mkdir()
    _run(tmp_path / "out")
    assert (tmp_path / "out" / "summary.json").exists()


def test_a_second_run_into_a_locked_directory_fails_at_once(tmp_path):
    out = tmp_path / "out"
    with RunDirectory(out):
        with pytest.raises(bc.ConfigError, match=rf"another bemcontact run \(process {os.getpid()}\)"):
            RunDirectory(out).__enter__()
    assert list(tmp_path.iterdir()) == []  # lock released, nothing written


def test_a_stale_lock_is_taken_over(tmp_path):
    dead = subprocess.Popen([sys.executable, "-c", "pass"])
    dead.wait()
    (tmp_path / ".out.lock").write_text(str(dead.pid))
    _run(tmp_path / "out")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"]


def test_a_kill_between_the_two_renames_is_recovered(tmp_path):
    """Killed after the old run was moved aside and before the new one was
    renamed in: the next run finds the old one and puts it back first."""
    out = tmp_path / "out"
    _run(out, files=("old.txt",))
    out.rename(tmp_path / ".out.old-dead")
    (tmp_path / ".out.tmp-dead").mkdir()
    (tmp_path / ".out.tmp-dead" / "half.txt").write_text("half")
    with RunDirectory(out) as rd:
        assert (out / "old.txt").read_text() == "old.txt"  # the previous complete run is back
        assert not list(tmp_path.glob(".out.*-dead"))
        with pytest.raises(RuntimeError), rd.staging() as tmp:
            (tmp / "new.txt").write_text("new")
            raise RuntimeError("killed while writing")
    assert sorted(p.name for p in out.iterdir()) == [MARKER, "old.txt"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"]


def test_unwritable_parent_is_refused_before_anything(tmp_path, monkeypatch):
    # (the permission test itself, not chmod: root may write anywhere)
    monkeypatch.setattr(os, "access", lambda path, mode: False)
    with pytest.raises(bc.ConfigError) as info:
        RunDirectory(tmp_path / "out" / "new")
    assert str(info.value) == f"{tmp_path}/out/new: --out: cannot write into {tmp_path}"
    assert list(tmp_path.iterdir()) == []


def test_forced_into_the_current_directory_touches_nothing_else(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "mine.txt").write_text("mine")
    _run(".", force=True)
    assert (tmp_path / "mine.txt").read_text() == "mine"
    assert (tmp_path / "summary.json").exists() and (tmp_path / "sub" / "a.txt").exists()
    assert pathlib.Path(MARKER).exists()


def test_dot_dot_creates_no_directory_on_the_way(tmp_path, monkeypatch):
    """`--out a/new/..` is `a`: the run goes into a/out-free `a`, and no
    `a/new` is created on the way."""
    monkeypatch.chdir(tmp_path)
    rd = RunDirectory("a/new/..")
    assert rd.path == tmp_path / "a"
    _run("a/new/..")
    assert sorted(p.name for p in (tmp_path / "a").iterdir()) == [MARKER, "sub", "summary.json"]
