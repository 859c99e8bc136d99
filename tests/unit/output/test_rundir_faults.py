"""Fault injection into the output directory: the writer failing at
each file, a kill at each stage of the swap, two runs racing for one
directory, and ``--out`` as a symbolic link.  After each, the directory holds
exactly one complete run (the old or the new), and nothing else is left."""

from __future__ import annotations

import builtins
import errno
import io
import json
import os
import pathlib
import shutil
import signal
import subprocess
import sys
import textwrap
import threading
import time

import pytest

import bemcontact as bc
from bemcontact.cli import main
from bemcontact.output import rundir
from bemcontact.output.rundir import MARKER, RunDirectory

from ..test_cli import problem

FILES = ("summary.json", "a.vtu", "sub/b.vtu", "sub/deeper/c.csv")


def _write_run(out, tag: str, files=FILES, **kw) -> None:
    with RunDirectory(out, **kw) as rd, rd.staging() as tmp:
        for f in files:
            (tmp / f).parent.mkdir(parents=True, exist_ok=True)
            (tmp / f).write_text(f"{tag}:{f}")


def _complete_run(out: pathlib.Path) -> str:
    """'old' or 'new' if ``out`` holds exactly one complete run of that tag
    (every file its manifest lists, nothing else, all of one run); fails
    otherwise."""
    assert out.is_dir(), f"{out} does not exist"
    listed = json.loads((out / MARKER).read_text())["files"]
    present = sorted(p.relative_to(out).as_posix() for p in out.rglob("*") if p.is_file())
    assert sorted([*listed, MARKER]) == present, (listed, present)
    tags = {(out / f).read_text().split(":", 1)[0] for f in listed}
    assert len(tags) == 1, f"files of two runs mixed: {tags}"
    for f in listed:
        assert (out / f).read_text() == f"{next(iter(tags))}:{f}"
    return tags.pop()


def _left_over(parent: pathlib.Path, name="out") -> list[str]:
    return sorted(p.name for p in parent.iterdir() if p.name != name)


# ----------------------------------------------------------------------------- writer failures


def _failing_open(monkeypatch, fail_at: int, counter: list[int]):
    """builtins.open and io.open raising ENOSPC at the ``fail_at``-th opening of
    a file for writing inside a staging directory (counted in ``counter``)."""
    real = builtins.open

    def fake(file, mode="r", *args, **kwargs):
        if any(c in mode for c in "wax+") and ".tmp-" in os.fspath(file):
            counter[0] += 1
            if counter[0] == fail_at:
                raise OSError(errno.ENOSPC, "No space left on device", os.fspath(file))
        return real(file, mode, *args, **kwargs)

    monkeypatch.setattr(builtins, "open", fake)
    monkeypatch.setattr(io, "open", fake)


def test_the_writer_failing_at_each_file_leaves_the_earlier_run(tmp_path, monkeypatch):
    """The real writer (summary, VTU, PVD, CSV, figure, manifest) made to fail
    at its k-th file, for every k: the call raises, the earlier run is there
    byte for byte, and no staging directory or lock is left."""
    pytest.importorskip("matplotlib")
    src = problem(tmp_path)
    pf = bc.load_problem(src)
    result = pf.solve()
    out = tmp_path / "out"
    pf.write(result, out)
    before = {p: p.read_bytes() for p in out.rglob("*") if p.is_file()}
    count = [0]
    with monkeypatch.context() as m:
        _failing_open(m, 0, count)  # counting only
        pf.write(result, tmp_path / "counted")
    shutil.rmtree(tmp_path / "counted")
    n = count[0]
    assert n >= len(before), (n, len(before))  # every file and the manifest opened
    for k in range(1, n + 1):
        with monkeypatch.context() as m:
            _failing_open(m, k, [0])
            with pytest.raises(OSError, match="No space left on device"):
                pf.write(result, out)
        assert {p: p.read_bytes() for p in out.rglob("*") if p.is_file()} == before, k
        assert _left_over(tmp_path) == ["tiny.toml"], k


def test_a_write_failure_through_the_command_is_one_line_exit_2(tmp_path, monkeypatch, capsys):
    src = problem(tmp_path)
    out = tmp_path / "out"
    assert main(["run", str(src), "--out", str(out), "--quiet"]) == 0
    before = {p: p.read_bytes() for p in out.rglob("*") if p.is_file()}
    _failing_open(monkeypatch, 3, [0])
    assert main(["run", str(src), "--out", str(out), "--quiet"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith(
        f"bemcontact: error: cannot write the results to {out}: No space left on device"), err
    assert {p: p.read_bytes() for p in out.rglob("*") if p.is_file()} == before
    assert _left_over(tmp_path) == ["tiny.toml"]


@pytest.mark.parametrize("stage", ["exchange", "rmtree"])
def test_a_failing_swap_step_leaves_one_complete_run(tmp_path, monkeypatch, stage):
    out = tmp_path / "out"
    _write_run(out, "old")

    def fail(*args, **kwargs):
        raise OSError(errno.EIO, "Input/output error")

    if stage == "exchange":
        monkeypatch.setattr(rundir, "_exchange", fail)
        with pytest.raises(OSError, match="Input/output error"):
            _write_run(out, "new")
        assert _complete_run(out) == "old"
    else:  # removing the old run fails: the new one is in place, the rest goes next time
        monkeypatch.setattr(rundir.shutil, "rmtree", lambda *a, **k: None)
        _write_run(out, "new")
        assert _complete_run(out) == "new"
        monkeypatch.undo()
        _write_run(out, "third")
        assert _complete_run(out) == "third"
    assert _left_over(tmp_path) == []


# ----------------------------------------------------------------------------- kills

_KILLER = textwrap.dedent("""
    import builtins, io, os, pathlib, shutil, sys
    from bemcontact.output import rundir
    kill_at, exchange = int(sys.argv[2]), sys.argv[3] == "exchange"
    if not exchange:
        rundir._LIBC = None  # a filesystem without renameat2: two renames
    events = [0]

    def step(name):
        events[0] += 1
        if events[0] == kill_at:
            os._exit(137)  # killed: no cleanup, no finally

    def wrap(owner, attr):
        real = getattr(owner, attr)
        def f(*a, **k):
            step(attr)
            return real(*a, **k)
        setattr(owner, attr, f)

    wrap(rundir, "_exchange")
    wrap(pathlib.Path, "rename")
    wrap(shutil, "rmtree")
    real_open = builtins.open
    def opener(file, mode="r", *a, **k):
        if "w" in mode and ".tmp-" in os.fspath(file):
            step("open")
        return real_open(file, mode, *a, **k)
    builtins.open = io.open = opener
    files = ("summary.json", "a.vtu", "sub/b.vtu", "sub/deeper/c.csv")
    with rundir.RunDirectory(sys.argv[1]) as rd, rd.staging() as tmp:
        for f in files:
            (tmp / f).parent.mkdir(parents=True, exist_ok=True)
            (tmp / f).write_text(f"new:{f}")
    print("events", events[0])
""")


@pytest.mark.parametrize("swap", ["exchange", "renames"])
def test_a_kill_at_each_stage_of_the_write_leaves_one_complete_run(tmp_path, swap):
    """A real process killed (os._exit) at each file written and at each step
    of the swap.  With the atomic exchange the directory holds one complete
    run at the instant of the kill; with two renames the next run restores
    it.  Either way the next run finds exactly one complete run and leaves
    nothing else behind."""
    env = {k: v for k, v in os.environ.items() if not k.startswith("PYTEST")}
    seen = set()
    k = 0
    while True:
        k += 1
        case = tmp_path / f"k{k}"
        case.mkdir()
        out = case / "out"
        _write_run(out, "old")
        proc = subprocess.run([sys.executable, "-c", _KILLER, str(out), str(k), swap],
                              capture_output=True, text=True, env=env, timeout=60)
        if proc.returncode == 0:
            events = int(proc.stdout.split()[-1])
            assert k == events + 1, (k, proc.stdout)
            assert _complete_run(out) == "new"
            break
        assert proc.returncode == 137, proc.stderr
        if swap == "exchange":
            seen.add(_complete_run(out))  # at the instant of the kill
        with RunDirectory(out):  # the next run: recovery
            pass
        seen.add(_complete_run(out))
        assert _left_over(case) == [], (k, _left_over(case))
    # 4 files and the manifest, the exchange (declined without renameat2: then
    # two renames), the removal of the old run
    assert k - 1 == {"exchange": 7, "renames": 9}[swap], k
    assert seen == {"old", "new"}


# ----------------------------------------------------------------------------- the lock


def test_racing_runs_never_write_at_once(tmp_path):
    """Threads entering and leaving one directory as fast as they can for 1 s
    (the lock file created, taken, unlinked and re-created under them): never
    two inside at once, and every thread got in."""
    out = tmp_path / "out"
    inside, most, entered = [0], [0], {}
    guard = threading.Lock()
    stop = time.monotonic() + 1.0

    def worker(i):
        entered[i] = 0
        while time.monotonic() < stop:
            rd = RunDirectory(out)
            try:
                rd.__enter__()
            except bc.ConfigError as exc:
                assert "another bemcontact run" in str(exc)
                continue
            with guard:
                inside[0] += 1
                most[0] = max(most[0], inside[0])
            time.sleep(0.0005)
            with guard:
                inside[0] -= 1
            rd.__exit__(None, None, None)
            entered[i] += 1

    threads = [threading.Thread(target=worker, args=(i,)) for i in range(6)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert most[0] == 1, most
    assert all(n > 0 for n in entered.values()), entered
    assert list(tmp_path.iterdir()) == []


def test_a_second_process_is_refused_and_a_killed_one_blocks_nothing(tmp_path, capsys):
    """Two runs into one --out: while one (a real process) holds the
    directory, `bemcontact run` into it is one line naming that process, exit
    2, nothing solved or written; once the holder is killed (SIGKILL: no
    cleanup) the next run goes ahead."""
    src = problem(tmp_path)
    out = tmp_path / "out"
    holder = subprocess.Popen(
        [sys.executable, "-c", "import sys, time\n"
         "from bemcontact.output.rundir import RunDirectory\n"
         "with RunDirectory(sys.argv[1]):\n"
         "    print('locked', flush=True); time.sleep(60)\n", str(out)],
        stdout=subprocess.PIPE, text=True)
    try:
        assert holder.stdout.readline().strip() == "locked"
        assert main(["run", str(src), "--out", str(out), "--quiet"]) == 2
        err = capsys.readouterr().err
        assert err == (f"bemcontact: error: {out}: --out: another bemcontact run (process "
                       f"{holder.pid}) is writing into it; wait for it or name another "
                       "directory\n"), err
        assert not out.exists()
    finally:
        holder.send_signal(signal.SIGKILL)
        holder.wait()
        holder.stdout.close()
    assert (tmp_path / ".out.lock").exists()  # left by the kill, but not held
    assert main(["run", str(src), "--out", str(out), "--quiet"]) == 0
    assert json.loads((out / "summary.json").read_text())["converged"] is True
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out", "tiny.toml"]


# ----------------------------------------------------------------------------- symbolic links


def test_out_as_a_symbolic_link_writes_into_its_target(tmp_path):
    """A link to a directory: the runs go into the target, the link stays a
    link, and no .old- copy of the link is left (it was replaced by a
    directory and its old self kept forever)."""
    (tmp_path / "real").mkdir()
    (tmp_path / "link").symlink_to("real")
    _write_run(tmp_path / "link", "old")
    _write_run(tmp_path / "link", "new")
    assert (tmp_path / "link").is_symlink()
    assert _complete_run(tmp_path / "real") == "new"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["link", "real"]


@pytest.mark.parametrize("target", ["nothing/here", "afile"])
def test_out_as_a_dangling_symbolic_link_is_refused_before_the_solve(
        tmp_path, capsys, monkeypatch, target):
    """``--out`` as a dangling symbolic link (or one to a file) is refused in
    one line before anything is read, not after the solve ("Not a
    directory")."""
    (tmp_path / "afile").write_text("mine")
    (tmp_path / "link").symlink_to(target)
    src = problem(tmp_path)
    monkeypatch.setattr(bc.ProblemFile, "solve", lambda *a, **k: pytest.fail("solved"))
    assert main(["run", str(src), "--out", str(tmp_path / "link")]) == 2
    what = "is not a directory" if target == "afile" else "does not exist"
    assert capsys.readouterr().err == (
        f"bemcontact: error: {tmp_path}/link: --out: is a symbolic link to {tmp_path}/{target}, "
        f"which {what}; create that directory or name another one\n")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["afile", "link", "tiny.toml"]


def test_a_directory_that_refuses_the_lock_fails_before_the_solve(tmp_path, capsys, monkeypatch):
    """Where DIR's parent cannot be written (EACCES for a user; root passes
    os.access everywhere, so the failure is injected at the lock, the first
    file a run creates): one line, exit 2, and the solve never starts."""
    src = problem(tmp_path)
    real = os.open

    def deny(path, flags, *args, **kwargs):
        if os.fspath(path).endswith(".lock"):
            raise PermissionError(errno.EACCES, "Permission denied", os.fspath(path))
        return real(path, flags, *args, **kwargs)

    monkeypatch.setattr(os, "open", deny)
    monkeypatch.setattr(bc.ProblemFile, "solve", lambda *a, **k: pytest.fail("solved"))
    out = tmp_path / "out"
    assert main(["run", str(src), "--out", str(out)]) == 2
    assert capsys.readouterr().err == (
        f"bemcontact: error: cannot write the results to {out}: Permission denied "
        f"({tmp_path}/.out.lock)\n")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["tiny.toml"]


@pytest.mark.parametrize("name_bytes, refused", [(241, False), (242, True), (245, True)])
def test_a_name_too_long_for_the_staging_directory_is_refused_before_the_solve(
        tmp_path, name_bytes, refused):
    """`.<name>.tmp-XXXXXXXX` is 14 bytes longer than DIR's name: a 245-byte
    name solved and then failed with "File name too long"; 241 bytes fit."""
    name = "o" * name_bytes
    if refused:
        with pytest.raises(bc.ConfigError) as info:
            RunDirectory(tmp_path / name)
        given = str(tmp_path / name)
        shown = f"{given[:80]}...{given[-80:]}"  # a long path is shown by its ends
        assert str(info.value) == (
            f"{shown}: --out: too long for this filesystem (its name is "
            f"{name_bytes} bytes, at most 241, leaving room for the files of a run); name a "
            "shorter one")
    else:
        _write_run(tmp_path / name, "new")
        assert _complete_run(tmp_path / name) == "new"


def test_a_path_too_long_for_the_files_of_a_run_is_refused(tmp_path):
    deep = tmp_path.joinpath(*["d" * 200] * 20)  # > 4,096 - 128 bytes
    with pytest.raises(bc.ConfigError, match=r"^.{80}\.\.\..{80}: --out: too long for this "
                       r"filesystem \(its path is \d+ bytes, at most 3968, leaving room"):
        RunDirectory(deep)
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("entry", ["link to a directory", "empty directory"])
def test_a_users_link_or_empty_folder_in_a_run_directory_is_refused(tmp_path, entry):
    """The walk for files the manifest does not list saw neither a link to a
    directory nor an empty folder, and the swap then deleted them."""
    out = tmp_path / "out"
    _write_run(out, "old")
    (tmp_path / "data").mkdir()
    (tmp_path / "data" / "keep.txt").write_text("mine")
    if entry == "link to a directory":
        (out / "sub" / "mydata").symlink_to(tmp_path / "data")
        name = "sub/mydata"
    else:
        (out / "sub" / "notes").mkdir()
        name = "sub/notes"
    with pytest.raises(bc.ConfigError, match=f"holds files bemcontact did not write \\({name}\\)"):
        _write_run(out, "new")
    _write_run(out, "new", force=True)  # beside them, untouched
    assert (out / name).exists() and (tmp_path / "data" / "keep.txt").read_text() == "mine"
    assert (out / "summary.json").read_text() == "new:summary.json"
