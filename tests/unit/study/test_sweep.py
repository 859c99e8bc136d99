"""bemcontact sweep on Dask: every point equal to a separate run,
failing points in the table, resume, 1 and N workers, bad input."""

from __future__ import annotations

import json
import os
import re
import shutil
import sys

import distributed  # installed by make (RUN_DEPS) and the test extra
import numpy as np
import pytest

import bemcontact as bc
from bemcontact.cli import main
from bemcontact.errors import ConfigError
from bemcontact.study import SweepOptions, run_sweep
from bemcontact.study.table import OUTPUTS, read_table

from .conftest import tiny_problem

MU = "contact.friction_coefficient"
TOP = "body[1].boundary_conditions.zmax.displacement[0]"
VARY = [f"{MU}=0.01,0.1", f"{TOP}=0.002,0.004"]
NUMBERS = ("normal_force", "tangential_force", "force_x", "force_y", "force_z", "peak_pressure",
           "slip_area")


@pytest.fixture(scope="module")
def client():
    with (distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=False,
                                   dashboard_address=":0") as cluster,
          distributed.Client(cluster) as c):
        yield c


@pytest.fixture(scope="module")
def swept(tmp_path_factory, client):
    tmp = tmp_path_factory.mktemp("sweep")
    path = tiny_problem(tmp)
    seen = []
    result = run_sweep(path, tmp / "out", vary=VARY, client=client,
                       progress=lambda done, total, row: seen.append((done, total, row["point"])))
    return tmp, path, result, seen


def _separate(tmp, mu, dx):
    """The point as its own problem file, solved as bemcontact run does."""
    p = tiny_problem(tmp, mu=str(mu), top=f"[{dx}, 0, -0.04]", name=f"sep_{mu}_{dx}.toml")
    return bc.load_problem(p).solve(threads=1)


def test_four_points_equal_separate_runs(swept):
    tmp, _, result, seen = swept
    assert [r["point"] for r in result.rows] == ["p0001", "p0002", "p0003", "p0004"]
    assert [(r[MU], r[TOP]) for r in result.rows] == [
        (0.01, 0.002), (0.01, 0.004), (0.1, 0.002), (0.1, 0.004)]
    assert (result.computed, result.resumed, result.failed) == (4, 0, 0)
    assert sorted(d for d, _, _ in seen) == [1, 2, 3, 4] and {t for _, t, _ in seen} == {4}
    slips = []
    for r in result.rows:
        ref = _separate(tmp, r[MU], r[TOP])
        assert r["status"] == "ok" and r["converged"] is True
        got = np.array([r[k] for k in NUMBERS])
        fr = ref.frame
        want = np.array([ref.normal_force, ref.tangential_force, *ref.contact_force,
                         fr.pressure.max(), fr.weights[fr.state == 2].sum()])
        assert np.abs(got - want).max() <= 1e-10 * np.abs(want).max(), (got, want)
        assert r["newton_iterations"] == ref.newton_iterations
        assert (r["stick"], r["slip"], r["open"]) == tuple(
            ref.frame.counts()[k] for k in ("stick", "slip", "open"))
        # the point's full output, as bemcontact run writes it
        s = json.loads((tmp / "out" / "points" / r["point"] / "summary.json").read_text())
        assert abs(s["normal_force"] - ref.normal_force) <= 1e-10 * ref.normal_force
        slips.append(r["slip"])
    assert slips == [3, 9, 0, 0]  # friction 0.01 slips, more with more shift; 0.1 sticks


def test_table_and_figure_written(swept):
    tmp, _, result, _ = swept
    rows = read_table(tmp / "out" / "table.csv")
    assert list(rows[0]) == ["point", MU, TOP, *OUTPUTS]
    assert len(rows) == 4
    for r, row in zip(rows, result.rows):
        assert float(r["normal_force"]) == row["normal_force"]  # repr: exact round trip
        assert r["status"] == "ok" and r["directory"] == f"points/{row['point']}"
    names = {f.name for f in result.files}
    assert "table.csv" in names
    pytest.importorskip("matplotlib")
    assert "sweep.png" in names and (tmp / "out" / "sweep.png").stat().st_size > 10_000


def test_point_files_rerun_alone(swept):
    """Each point's problem file is what bemcontact run solves for it."""
    tmp, _, result, _ = swept
    pf = bc.load_problem(tmp / "out" / "points" / "p0002.toml")
    assert pf.pair.friction_coefficient == 0.01
    r = pf.solve(threads=1)
    assert abs(r.normal_force - result.rows[1]["normal_force"]) <= 1e-10 * r.normal_force


def test_failing_point_reported_others_complete(tmp_path, client):
    path = tiny_problem(tmp_path)
    result = run_sweep(path, tmp_path / "out", vary=[f"{MU}=0.01", "solver.max_iterations=50,2"],
                       client=client)
    ok, bad = result.rows
    assert ok["status"] == "ok" and ok["newton_iterations"] > 2
    assert bad["status"] == "not converged" and "did not converge" in bad["error"]
    assert result.failed == 1
    rows = read_table(tmp_path / "out" / "table.csv")
    assert [r["status"] for r in rows] == ["ok", "not converged"]
    assert "did not converge" in rows[1]["error"]
    s = json.loads((tmp_path / "out" / "points" / "p0002" / "summary.json").read_text())
    assert s["converged"] is False  # the diagnostic summary, as bemcontact run writes it


def test_resume_computes_only_unfinished_points(tmp_path, client, swept):
    _, path, first, _ = swept
    out = tmp_path / "out"
    shutil.copytree(swept[0] / "out", out)
    # interrupted: two points had not finished (no record), the table not yet written
    for name in ("p0002", "p0004"):
        (out / "records" / f"{name}.json").unlink()
        shutil.rmtree(out / "points" / name)
    (out / "table.csv").unlink()
    result = run_sweep(path, out, vary=VARY, client=client)
    assert (result.computed, result.resumed) == (2, 2)
    for a, b in zip(result.rows, first.rows):
        for k in NUMBERS:
            assert abs(a[k] - b[k]) <= 1e-10 * abs(b["normal_force"])
    assert len(read_table(out / "table.csv")) == 4
    again = run_sweep(path, out, vary=VARY, client=client)
    assert (again.computed, again.resumed) == (0, 4)


def test_one_and_two_workers_identical(tmp_path, swept):
    _, path, two, _ = swept
    with (distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False,
                                   dashboard_address=":0") as cluster,
          distributed.Client(cluster) as c):
        one = run_sweep(path, tmp_path / "one", vary=VARY, client=c)
    for a, b in zip(one.rows, two.rows):
        for k in NUMBERS:
            assert abs(a[k] - b[k]) <= 1e-10 * abs(b["normal_force"]), (k, a[k], b[k])
        assert a["newton_iterations"] == b["newton_iterations"]


def test_sweep_table_in_problem_file(tmp_path, client):
    path = tiny_problem(tmp_path, extra='[sweep]\npoints = [{"contact.friction_coefficient" = '
                        '0.3}, {"contact.friction_coefficient" = 0.01, "solver.penalty" = 2.0}]\n')
    assert bc.load_problem(path).pair.friction_coefficient == 0.1  # run ignores [sweep]
    result = run_sweep(path, tmp_path / "out", client=client)
    assert [r.get(MU) for r in result.rows] == [0.3, 0.01]
    assert result.rows[1]["solver.penalty"] == 2.0 and result.rows[0].get("solver.penalty") is None
    assert all(r["status"] == "ok" for r in result.rows)


# ------------------------------------------------------------------ command line


def test_command_line_sweep_on_a_scheduler(tmp_path, client, capsys):
    path = tiny_problem(tmp_path)
    out = tmp_path / "out"
    code = main(["sweep", str(path), "--vary", f"{MU}=0.01,0.1", "--out", str(out),
                 "--scheduler", client.scheduler.address])
    captured = capsys.readouterr()
    assert code == 0, captured.err
    assert "2 point(s), 2 ok, 0 failed (2 computed, 0 finished before)" in captured.out
    assert "point 2/2" in captured.err
    rows = read_table(out / "table.csv")
    assert [float(r[MU]) for r in rows] == [0.01, 0.1]


@pytest.mark.parametrize("vary, message", [
    (["contact.friction_coeficient=0.1,0.2"],
     r"tiny\.toml: contact\.friction_coeficient: unknown key, got 'friction_coeficient' "
     r"\(did you mean 'friction_coefficient'\?\)$"),
    ([f"{MU}=abc,0.2"],
     r"tiny\.toml: sweep point 1 \(contact\.friction_coefficient = \"abc\"\): "
     r"contact\.friction_coefficient: must be a number, not a string, got 'abc'$"),
    (['body[1].boundary_conditions.zmax.displacement=[0,0,-0.04],["free",0,-0.04]'],
     r"tiny\.toml: body\[1\]\.boundary_conditions\.zmax\.displacement: changes the kind of a "
     r"boundary condition .*upper: region 'zmax' component x displacement -> traction.*"),
    ([f"{MU}"], r"tiny\.toml: --vary: must be KEY=VALUE,VALUE,\.\.\."),
    (["body.material.youngs_modulus=1e4"], r"is an array of \[\[body\]\] sections"),
])
def test_bad_input_one_line_exit_2_nothing_written(tmp_path, capsys, vary, message):
    path = tiny_problem(tmp_path)
    out = tmp_path / "out"
    argv = ["sweep", str(path), "--out", str(out)]
    for v in vary:
        argv += ["--vary", v]
    code = main(argv)
    err = capsys.readouterr().err
    assert code == 2
    assert err.count("\n") == 1 and err.startswith("bemcontact: error: "), err
    assert re.search(message, err.strip()), err
    assert not out.exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["tiny.toml"]


def test_unreachable_scheduler(tmp_path, capsys):
    path = tiny_problem(tmp_path)
    out = tmp_path / "out"
    code = main(["sweep", str(path), "--vary", f"{MU}=0.1", "--out", str(out), "--scheduler",
                 "tcp://127.0.0.1:9", "--timeout", "1"])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1, err
    assert err.startswith("bemcontact: error: cannot reach the Dask scheduler at "
                          "tcp://127.0.0.1:9: ")
    assert not out.exists()


def test_without_dask_one_line_names_the_extra(tmp_path, capsys, monkeypatch):
    monkeypatch.setitem(sys.modules, "distributed", None)
    out = tmp_path / "out"
    code = main(["sweep", str(tiny_problem(tmp_path)), "--vary", f"{MU}=0.1", "--out", str(out)])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1
    assert 'pip install "bemcontact[sweep]"' in err
    assert not out.exists()


def test_other_sweep_in_out_refused(swept, capsys):
    tmp, path, _, _ = swept
    code = main(["sweep", str(path), "--vary", f"{MU}=0.2", "--out", str(tmp / "out")])
    err = capsys.readouterr().err
    assert code == 2 and "holds another sweep" in err and err.count("\n") == 1


def test_options_checked():
    with pytest.raises(ConfigError,
                       match=r"^SweepOptions\.retries must be an integer in \[0, 100\], got -1$"):
        SweepOptions(retries=-1)
    assert SweepOptions().threads == 1 and SweepOptions().workers is None


def test_worker_killed_during_a_task_is_rerun(tmp_path, swept):
    """A real worker process killed (SIGKILL) while it runs a point: Dask
    runs the task again on a restarted or other worker and the table is
    complete, with the same numbers."""
    _, path, ref, _ = swept
    marker = tmp_path / "killed"

    class KillOnce(distributed.WorkerPlugin):
        """Kills its worker process when p0002 starts executing, once."""

        def setup(self, worker):
            self.worker = worker

        def transition(self, key, start, finish, **kwargs):
            import os
            import signal

            if finish == "executing" and "p0002" in str(key):
                try:
                    fd = os.open(marker, os.O_CREAT | os.O_EXCL | os.O_WRONLY)
                except FileExistsError:
                    return
                os.write(fd, str(os.getpid()).encode())
                os.close(fd)
                os.kill(os.getpid(), signal.SIGKILL)

    with (distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                   dashboard_address=":0", silence_logs=50) as cluster,
          distributed.Client(cluster) as c):
        c.register_plugin(KillOnce())
        pids = set(c.run(lambda: __import__("os").getpid()).values())
        result = run_sweep(path, tmp_path / "out", vary=VARY, client=c)
    assert int(marker.read_text()) in pids  # a worker of this cluster was killed
    assert [r["status"] for r in result.rows] == ["ok"] * 4
    for a, b in zip(result.rows, ref.rows):
        for k in NUMBERS:
            assert abs(a[k] - b[k]) <= 1e-10 * abs(b["normal_force"]), (k, a[k], b[k])
    assert len(read_table(tmp_path / "out" / "table.csv")) == 4


def test_command_line_local_cluster(tmp_path, capsys, swept):
    """Without --scheduler: a local cluster of worker processes."""
    _, path, ref, _ = swept
    out = tmp_path / "out"
    code = main(["sweep", str(path), "--vary", VARY[0], "--vary", VARY[1], "--out", str(out),
                 "--workers", "1"])
    captured = capsys.readouterr()
    assert code == 0, captured.err
    assert f"sweep of {path}: 4 point(s)" in captured.err
    rows = read_table(out / "table.csv")
    assert [float(r["normal_force"]) for r in rows] == pytest.approx(
        [r["normal_force"] for r in ref.rows], rel=1e-10, abs=0)


def test_the_workers_environment_is_theirs_only(monkeypatch):
    """The local cluster's workers have Dask's pre-spawn environment (one
    BLAS thread, ...); this process has it neither while the fork server or
    the workers start nor after the cluster (left behind, it made every
    process started from here afterwards single-threaded)."""
    from bemcontact.study import sweep, workers

    names = workers.worker_environ()
    for k in [*names, "__DASK_PARENT_PID"]:
        monkeypatch.delenv(k, raising=False)
    before = dict(os.environ)
    method = workers.start_fork_server()
    assert dict(os.environ) == before
    with sweep._connect(SweepOptions(workers=1), None, method) as c:
        assert dict(os.environ) == before
        seen = c.run(lambda: {k: __import__("os").environ.get(k) for k in names})
    assert dict(os.environ) == before
    assert len(seen) == 1
    assert all(v is not None for v in next(iter(seen.values())).values()), seen


def test_interrupted_then_resumed(tmp_path, client, swept):
    """Ctrl-C after the first finished point: the table holds the finished
    points, and the same command computes only the others."""
    _, path, ref, _ = swept
    out = tmp_path / "out"

    def interrupt(done, total, row):
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        run_sweep(path, out, vary=VARY, client=client, progress=interrupt)
    finished = read_table(out / "table.csv")
    assert len(finished) == 1 and finished[0]["status"] == "ok"
    assert len(list((out / "records").glob("*.json"))) == 1
    # a command interrupted ends its process and the points it ran; this
    # client's in-process workers go on with the cancelled points that had
    # started, which would write the same point directories as the resumed
    # run: wait for them (measured: one fresh-clone run in four on a loaded
    # 2-core machine raced there)
    import time

    deadline = time.monotonic() + 120.0
    while any(client.processing().values()) and time.monotonic() < deadline:
        time.sleep(0.1)
    result = run_sweep(path, out, vary=VARY, client=client)
    assert (result.computed, result.resumed) == (3, 1)
    assert all(r["status"] == "ok" for r in result.rows), result.rows
    assert [r["normal_force"] for r in result.rows] == pytest.approx(
        [r["normal_force"] for r in ref.rows], rel=1e-10, abs=0)


def test_command_line_failed_point_exit_3(tmp_path, client, capsys):
    out = tmp_path / "out"
    code = main(["sweep", str(tiny_problem(tmp_path)), "--vary", f"{MU}=0.01",
                 "--vary", "solver.max_iterations=50,2", "--out", str(out),
                 "--scheduler", client.scheduler.address])
    captured = capsys.readouterr()
    assert code == 3
    assert "2 point(s), 1 ok, 1 failed" in captured.out
    assert "p0002: not converged: contact solve did not converge" in captured.err
    assert [r["status"] for r in read_table(out / "table.csv")] == ["ok", "not converged"]


def test_bodies_far_from_the_origin(tmp_path, client):
    """As bemcontact run: solved relative to the bodies' own origin and the
    results written at their position (frame.csv equal to a separate run's)."""
    path = tiny_problem(tmp_path)
    text = path.read_text()
    for a, b in (("[0, 0, 0], upper = [2, 2, 2]", "[1000, 0, 0], upper = [1002, 2, 2]"),
                 ("[0, 0, 2], upper = [2, 2, 4]", "[1000, 0, 2], upper = [1002, 2, 4]")):
        assert a in text
        text = text.replace(a, b)
    path.write_text(text)
    pf = bc.load_problem(path)
    assert pf.origin is not None  # the case of contact/origin.py
    result = run_sweep(path, tmp_path / "out", vary=[f"{MU}=0.01"], client=client)
    assert result.rows[0]["status"] == "ok"
    assert main(["run", str(tmp_path / "out" / "points" / "p0001.toml"), "--out",
                 str(tmp_path / "run"), "--quiet", "--threads", "1"]) == 0

    def frame(d):
        return np.loadtxt(d / "frame.csv", delimiter=",", skiprows=1)

    got, want = frame(tmp_path / "out" / "points" / "p0001"), frame(tmp_path / "run")
    assert got.shape == want.shape and want[:, 0].min() >= 1000.0  # x at the bodies' position
    assert np.abs(got - want).max() <= 1e-10 * np.abs(want).max()


def test_a_point_follows_its_pairs_method_on_the_grid(tmp_path):
    """A point whose pair says ``method = "multiscale"`` (or ``"auto"`` on
    coarse meshes) is solved on the contact grid as `bemcontact run` solves
    it, not by the full path on its coarse meshes: the row holds the grid's
    forces (the example's 2,633.6 N, tests/test_examples.py) and counts, and
    the point's directory the grid's files."""
    import pathlib

    from bemcontact.study.sweep import run_point

    example = pathlib.Path(__file__).resolve().parents[3] / "examples" / "cattaneo_mindlin_multiscale.toml"
    text = example.read_text().replace("[contact]", '[output]\nfigures = false\ndefault_stresses = false\n\n[contact]', 1)
    point = tmp_path / "point.toml"
    point.write_text(text)
    out = tmp_path / "out"
    row = run_point(str(point), str(out), "g", str(tmp_path / "cache"), 1)
    assert row["status"] == "ok", row
    assert row["normal_force"] == pytest.approx(2633.6, rel=1e-3)
    # the platen's 396 N along x and the coarse sphere's lateral 0.026 N
    # (tests/test_examples.py)
    assert row["tangential_force"] == pytest.approx(396.0, rel=1e-8)
    assert row["stick"] > 0 and row["slip"] > 0 and row["increments"] == 5
    assert (out / "grid.csv").is_file() and not (out / "frame.csv").exists()


def test_a_rolling_point_has_the_creep_force_columns(tmp_path):
    """A point whose last step rolls: its row holds the creep force on the
    second body in the rolling frame and its ratio to mu F_n (the example's
    F_x = 64.32 N, tests/test_examples.py), and the table its columns; a
    creepage component is a sweep key ([0] or [1] of the pair)."""
    import pathlib

    from bemcontact.problemfile.checks import Checker
    from bemcontact.errors import ConfigError
    from bemcontact.study.points import check_key
    from bemcontact.study.sweep import run_point
    from bemcontact.study.table import ROLLING_OUTPUTS, read_table, write_table

    example = pathlib.Path(__file__).resolve().parents[3] / "examples" / "rolling_ball_multiscale.toml"
    text = example.read_text().replace("[contact]", '[output]\nfigures = false\ndefault_stresses = false\n\n[contact]', 1)
    point = tmp_path / "point.toml"
    point.write_text(text)
    row = run_point(str(point), str(tmp_path / "out"), "g", str(tmp_path / "cache"), 1)
    assert row["status"] == "ok", row
    assert row["creep_force_x"] == pytest.approx(64.32, rel=1e-3)
    assert row["creep_ratio_x"] == pytest.approx(64.32 / (0.3 * row["normal_force"]), rel=1e-3)
    write_table(tmp_path, [], [row])
    assert set(ROLLING_OUTPUTS) <= set(read_table(tmp_path / "table.csv")[0])
    chk = Checker("f.toml", tmp_path)
    assert check_key(chk, "step[1].rolling.creepage[1]") == ["step", 1, "rolling", "creepage", 1]
    with pytest.raises(ConfigError, match=r"has 2 components"):
        check_key(chk, "step[1].rolling.creepage[2]")
