"""Ctrl-C during gmsh meshing (which must not swallow it and carry on),
inside compiled code (where Python sees a signal only when the LU or the H-LU
returns), through real processes: one line, exit 130 within a second or two,
the output directory as it was and no lock left."""

from __future__ import annotations

import os
import queue
import signal
import subprocess
import sys
import textwrap
import threading
import time

import pytest

from bemcontact.cli import main

from .test_cli import ROOT, problem

ENV = {k: v for k, v in os.environ.items() if not k.startswith("PYTEST")}
ENV.setdefault("OMP_NUM_THREADS", "1")


#: Longest wait for the line ``_interrupt`` waits for (a loaded machine is
#: slow, but a test must never hang), and for the exit after the signal.
LINE_TIMEOUT = 300.0
EXIT_TIMEOUT = 60.0


def _lines(stream, into: queue.Queue) -> None:
    with stream:
        for line in stream:
            into.put(line)
    into.put(None)  # the end of the stream


def _interrupt(proc: subprocess.Popen, after_line: str | None = None, delay: float = 0.0):
    """SIGINT to ``proc`` (after a stderr line containing ``after_line``, then
    ``delay`` s); returns (exit code, seconds from the signal, the rest of stderr).
    Its stdout is read and dropped; a process that does not print the line
    within LINE_TIMEOUT s or end within EXIT_TIMEOUT s of the signal is killed
    and the test fails."""
    err: queue.Queue = queue.Queue()
    readers = [threading.Thread(target=_lines, args=(proc.stderr, err), daemon=True),
               threading.Thread(target=_lines, args=(proc.stdout, queue.Queue()), daemon=True)]
    for reader in readers:
        reader.start()
    try:
        if after_line is not None:
            deadline = time.monotonic() + LINE_TIMEOUT
            before = []
            while True:
                try:
                    line = err.get(timeout=max(deadline - time.monotonic(), 0.0))
                except queue.Empty:
                    pytest.fail(f"{after_line!r} not printed within {LINE_TIMEOUT:g} s; "
                                f"stderr so far: {''.join(before)!r}")
                if line is None:
                    pytest.fail(f"{after_line!r} never printed; exit {proc.wait()}; "
                                f"stderr: {''.join(before)!r}")
                if after_line in line:
                    break
                before.append(line)
        time.sleep(delay)
        proc.send_signal(signal.SIGINT)
        start = time.perf_counter()
        try:
            proc.wait(timeout=EXIT_TIMEOUT)
        except subprocess.TimeoutExpired:
            pytest.fail(f"still running {EXIT_TIMEOUT:g} s after SIGINT")
        seconds = time.perf_counter() - start
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    for reader in readers:
        reader.join()  # the process has ended: its pipes are at their end
    rest = []
    while (line := err.get()) is not None:
        rest.append(line)
    return proc.returncode, seconds, "".join(rest)


def _tree(directory):
    return {p.relative_to(directory): p.read_bytes() for p in directory.rglob("*") if p.is_file()}


def test_ctrl_c_during_the_solve_of_a_real_run(tmp_path):
    """Interrupted in the condensation (LAPACK and the compiled core): exit 130
    within 3 s (2 s of grace for Python to see it, then the watcher), one
    line, the earlier run in DIR untouched, no lock, no staging directory."""
    out = tmp_path / "out"
    assert main(["run", str(problem(tmp_path)), "--out", str(out), "--quiet"]) == 0
    before = _tree(out)
    src = tmp_path / "mid.toml"
    src.write_text((ROOT / "examples" / "two_cubes_similar.toml").read_text()
                   .replace("divisions = 6,", "divisions = 12,")
                   .replace("divisions = 5,", "divisions = 11,"))
    proc = subprocess.Popen(
        [sys.executable, "-m", "bemcontact", "run", str(src), "--out", str(out), "--progress",
         "lines"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=ENV)
    code, seconds, err = _interrupt(proc, "condensation lower ...", 0.3)
    assert code == 130, err
    assert err.splitlines()[-1] == "bemcontact: interrupted" and "Traceback" not in err, err
    assert err.count("interrupted") == 1, err
    assert seconds < 3.0, seconds
    assert _tree(out) == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["mid.toml", "out", "tiny.toml"]


#: ``bemcontact check ARGS`` with one line on stderr, ``meshing MODEL``, as
#: gmsh starts meshing each model: the cue for the signal (the command itself
#: prints nothing while it meshes).
_ANNOUNCED_MESHING = textwrap.dedent("""
    import sys
    import gmsh
    from bemcontact.cli import main
    generate = gmsh.model.mesh.generate
    def announced(dim=3):
        print("meshing", gmsh.model.getCurrent(), file=sys.stderr, flush=True)
        generate(dim)
    gmsh.model.mesh.generate = announced
    sys.exit(main(["check", *sys.argv[1:]]))
""")


def test_ctrl_c_during_gmsh_meshing_of_a_real_check(tmp_path):
    """A cap meshed for a second or more (fine_size 0.05 within 3 mm: gmsh
    about 1.1 s of a check of about 10 s on a 2-core AMD EPYC): Ctrl-C 0.3 s
    after gmsh has started meshing it (the line the child prints then, not a
    fixed time, which on a loaded machine could come before the meshing)
    ends the check in under 3 s, one line, exit 130 (a swallowed Ctrl-C
    meshed on to the end, exit 0)."""
    pytest.importorskip("gmsh")
    src = tmp_path / "slow.toml"
    src.write_text((ROOT / "examples" / "hertz_sphere_on_block.toml").read_text().replace(
        "fine_size = 0.1, coarse_size = 2.5, fine_radius = 0.7, order = 1",
        "fine_size = 0.05, coarse_size = 2.5, fine_radius = 3, order = 1"))
    proc = subprocess.Popen([sys.executable, "-c", _ANNOUNCED_MESHING, str(src)],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=ENV)
    code, seconds, err = _interrupt(proc, "meshing spherical_cap", 0.3)
    assert (code, err) == (130, "bemcontact: interrupted\n")
    assert seconds < 3.0, seconds


def test_gmsh_stops_refining_once_interrupted():
    """In process: the size callback sends SIGINT on its first call; gmsh is
    then answered the coarse size (the user's size function is not called
    again) and KeyboardInterrupt is raised once it has finished."""
    pytest.importorskip("gmsh")
    from bemcontact.mesh.mesher import mesh_with_gmsh

    calls = []

    def size(x, y, z):
        calls.append(1)
        if len(calls) == 1:
            os.kill(os.getpid(), signal.SIGINT)
        return 0.01  # a unit sphere at 0.01: about 300,000 elements

    def build(gmsh):
        vol = gmsh.model.occ.addSphere(0, 0, 0, 1)
        gmsh.model.occ.synchronize()
        tags = [t for _, t in gmsh.model.getBoundary([(3, vol)], oriented=False)]
        gmsh.model.addPhysicalGroup(2, tags, name="surface")

    start = time.perf_counter()
    with pytest.raises(KeyboardInterrupt):
        mesh_with_gmsh(build, (0.01, 0.5), 1, "sphere", size)
    assert len(calls) == 1
    assert time.perf_counter() - start < 5.0
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler


_HOLD = textwrap.dedent("""
    import signal, sys, time
    from bemcontact.output.rundir import InterruptGuard, RunDirectory
    with InterruptGuard(grace=0.5) as guard, RunDirectory(sys.argv[1]) as rd:
        guard.out = rd
        signal.signal(signal.SIGINT, lambda *a: None)  # Python never sees it: as in compiled code
        if sys.argv[2] == "writing":
            with rd.staging() as tmp:
                print("ready", flush=True)
                time.sleep(30)
        print("ready", flush=True)
        time.sleep(30)
""")


@pytest.mark.parametrize("stage", ["solving", "writing"])
def test_the_watcher_ends_a_run_stuck_outside_python(tmp_path, stage):
    """The main thread never returns to Python: 0.5 s after Ctrl-C the
    watcher releases the lock and ends the process (exit 130, one line);
    while a run is being written it leaves it to Python."""
    out = tmp_path / "new" / "out"
    proc = subprocess.Popen([sys.executable, "-c", _HOLD, str(out), stage],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=ENV)
    assert proc.stdout.readline().strip() == "ready"
    assert (tmp_path / "new" / ".out.lock").exists()
    proc.send_signal(signal.SIGINT)
    start = time.perf_counter()
    if stage == "solving":
        _, err = proc.communicate(timeout=30)
        assert (proc.returncode, err) == (130, "bemcontact: interrupted\n")
        assert time.perf_counter() - start < 2.5
        assert list(tmp_path.iterdir()) == []  # lock and the directory made for it gone
    else:
        time.sleep(1.5)
        assert proc.poll() is None  # still writing
        proc.kill()
        proc.communicate()
