"""The bemcontact command: exit codes, messages, and what it writes (or not)."""

from __future__ import annotations

import importlib.metadata
import json
import pathlib
import subprocess
import sys

import numpy as np
import pytest

import bemcontact as bc
from bemcontact.cli import main

ROOT = pathlib.Path(__file__).resolve().parents[2]

TINY = """\
units = {{ length = "mm", force = "N", stress = "MPa" }}

[[body]]
name = "lower"
mesh = {{ box = {{ lower = [0, 0, 0], upper = [2, 2, 2], divisions = 1 }} }}
material = {{ youngs_modulus = {E}, poisson_ratio = 0.3 }}
[body.boundary_conditions.zmin]
displacement = [0, 0, 0]

[[body]]
name = "upper"
mesh = {{ box = {{ lower = [0, 0, 2], upper = [2, 2, 4], divisions = 1 }} }}
material = {{ youngs_modulus = 1e4, poisson_ratio = 0.3 }}
[body.boundary_conditions.zmax]
displacement = {top}

[contact]
surfaces = ["zmax", "zmin"]
friction_coefficient = {mu}
"""


def problem(tmp_path, E="1e4", top="[0, 0, -0.04]", mu="0.1"):
    p = tmp_path / "tiny.toml"
    p.write_text(TINY.format(E=E, top=top, mu=mu))
    return p


def test_run_writes_results_and_prints_a_summary(tmp_path, capsys):
    out = tmp_path / "out"
    code = main(["run", str(problem(tmp_path)), "--out", str(out), "--threads", "1"])
    captured = capsys.readouterr()
    assert code == 0, captured.err
    assert captured.err == ""
    s = json.loads((out / "summary.json").read_text())
    assert s["converged"] is True and s["names"] == ["lower", "upper"]
    assert s["problem"]["file"] == str(tmp_path / "tiny.toml")
    assert f"normal force      {s['normal_force']:.6g} N" in captured.out
    assert "tangential force" in captured.out
    assert "lower (zmax, " in captured.out and "stick" in captured.out
    assert f"results in {out}" in captured.out
    assert (out / "lower_interface.csv").is_file() and (out / "frame.vtu").is_file()


def test_quiet_prints_nothing(tmp_path, capsys):
    assert main(["run", str(problem(tmp_path)), "--out", str(tmp_path / "o"), "--quiet"]) == 0
    assert capsys.readouterr().out == ""


@pytest.mark.parametrize(
    "kwargs, field, value",
    [
        ({"E": "-1"}, "body[0].material.youngs_modulus", "-1"),
        ({"mu": "true"}, "contact.friction_coefficient", "True"),
        ({"top": '["free", "free", "fixed"]'}, "body[1].boundary_conditions.zmax.displacement[2]",
         "'fixed'"),
    ],
)
def test_bad_input_is_one_line_exit_2_nothing_written(tmp_path, capsys, kwargs, field, value):
    out = tmp_path / "out"
    path = problem(tmp_path, **kwargs)
    code = main(["run", str(path), "--out", str(out)])
    captured = capsys.readouterr()
    assert code == 2
    assert captured.out == ""
    lines = captured.err.splitlines()
    assert len(lines) == 1, captured.err
    assert lines[0].startswith(f"bemcontact: error: {path}: {field}: ")
    assert lines[0].endswith(f"got {value}")
    assert not out.exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["tiny.toml"]


def test_missing_problem_file(tmp_path, capsys):
    assert main(["run", str(tmp_path / "none.toml"), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "none.toml: cannot read the problem file" in err
    assert list(tmp_path.iterdir()) == []


def test_out_is_a_file(tmp_path, capsys):
    (tmp_path / "o").write_text("x")
    assert main(["run", str(problem(tmp_path)), "--out", str(tmp_path / "o")]) == 2
    assert "--out: exists and is not a directory" in capsys.readouterr().err


def test_debug_reraises(tmp_path):
    with pytest.raises(bc.ConfigError, match="youngs_modulus"):
        main(["run", str(problem(tmp_path, E="0")), "--out", str(tmp_path / "o"), "--debug"])


def test_unrestrained_body_exit_3_with_diagnostic_summary(tmp_path, capsys):
    """Frictionless contact and only a z displacement on the upper cube: it
    is free to slide and to turn about z, so the Newton matrix is singular."""
    out = tmp_path / "out"
    path = problem(tmp_path, top='["free", "free", -0.04]', mu="0")
    code = main(["run", str(path), "--out", str(out)])
    captured = capsys.readouterr()
    assert code == 3
    assert captured.out == ""
    assert captured.err.startswith("bemcontact: error: contact solve did not converge")
    assert "residual history: [" in captured.err
    assert "states at the last iterate, upper:" in captured.err
    s = json.loads((out / "summary.json").read_text())
    assert s["converged"] is False
    assert "singular" in s["error"]
    assert s["load_steps"][0]["residual_history"]
    assert sorted(p.name for p in out.iterdir()) == [".bemcontact-run.json", "summary.json"]


def test_version_and_no_command(capsys):
    with pytest.raises(SystemExit) as info:
        main(["--version"])
    assert info.value.code == 0
    assert capsys.readouterr().out.strip() == f"bemcontact {bc.__version__}"
    assert main([]) == 2
    assert "a command is required" in capsys.readouterr().err


def test_console_script_and_module_entry_points():
    (ep,) = importlib.metadata.entry_points(group="console_scripts", name="bemcontact")
    assert ep.value == "bemcontact.cli:main"
    out = subprocess.run(
        [sys.executable, "-m", "bemcontact", "--version"], capture_output=True, text=True,
        check=True,
    ).stdout
    assert out.strip() == f"bemcontact {bc.__version__}"


@pytest.mark.parametrize(
    "old, new, field, value",
    [
        # five classes of bad input: a misspelt key, a wrong type, an unknown
        # region, a value out of range, contact surfaces that never meet
        ("friction_coefficient =", "friction_coeficient =", "contact.friction_coeficient",
         "did you mean 'friction_coefficient'"),
        ("upper = [2, 2, 2], divisions = 1", "upper = [2, 2, 2], divisions = \"one\"",
         "body[0].mesh.box.divisions", "'one'"),
        ("[body.boundary_conditions.zmin]", "[body.boundary_conditions.zbottom]",
         "body[0].boundary_conditions.zbottom", "zbottom"),
        ("friction_coefficient = 0.1", "friction_coefficient = -0.1",
         "contact.friction_coefficient", "-0.1"),
        ("lower = [0, 0, 2], upper = [2, 2, 4]", "lower = [5, 0, 2], upper = [7, 2, 4]",
         "contact.surfaces", "do not overlap"),
    ],
)
def test_bad_input_classes(tmp_path, capsys, old, new, field, value):
    path = problem(tmp_path)
    text = path.read_text()
    assert old in text
    path.write_text(text.replace(old, new, 1))
    out = tmp_path / "out"
    code = main(["run", str(path), "--out", str(out)])
    captured = capsys.readouterr()
    assert code == 2, captured
    lines = captured.err.splitlines()
    assert len(lines) == 1, captured.err
    assert lines[0].startswith(f"bemcontact: error: {path}: {field}")
    assert value in lines[0]
    assert "Traceback" not in captured.err and not out.exists()


def test_bench_one_body_writes_a_json_record(tmp_path, capsys):
    import json

    path = tmp_path / "one.json"
    assert main(["bench", "one-body", "--nodes", "400", "--method", "hmatrix", "--eps", "1e-7",
                 "--leaf", "24", "--threads", "2", "--json", str(path)]) == 0
    rec = json.loads(path.read_text())
    assert rec == json.loads(capsys.readouterr().out)
    # 6 n^2 + 36 n - 18 nodes with n = 6: 414
    assert rec["nodes"] == 414 and rec["unknowns"] == 3 * 414 and rec["method"] == "hmatrix"
    assert rec["leaf_size"] == 24
    for key in ("assembly_s", "factor_s", "solve_s", "newton_s", "newton_iterations",
                "peak_rss_mb", "compressed_mb", "dense_mb", "error", "normal_force", "threads",
                "version"):
        assert key in rec
    # exact linear field: the error is the H-matrix's, a few eps (measured 2e-7)
    assert rec["error"] < 1e-5 and rec["threads"] == 2


def test_bench_bad_arguments_exit_2(tmp_path, capsys):
    assert main(["bench", "one-body", "--nodes", "400", "--json", str(tmp_path / "no" / "x.json")]) == 2
    assert "does not exist" in capsys.readouterr().err
    assert main(["bench", "one-body", "--nodes", "400", "--eps", "2"]) == 2
    assert "--eps" in capsys.readouterr().err
    assert not (tmp_path / "no").exists()


def test_bench_two_cubes_record(tmp_path):
    import json

    path = tmp_path / "two.json"
    assert main(["bench", "two-cubes", "--divisions", "3", "--case", "dissimilar", "--json",
                 str(path)]) == 0
    rec = json.loads(path.read_text())
    assert rec["case"] == "two-cubes-dissimilar" and rec["divisions"] == 3
    assert rec["newton_iterations"] >= 1 and 0 < rec["newton_fraction"] < 1
    # the paper's bounds for the dissimilar cubes (docs/validation.md): 800-1077 N
    assert 800 < rec["normal_force"] < 1077
    assert rec["method"] == "dense" and rec["factor_s"] is None
    # the compressed path: same force (eps 1e-8: to 1e-6), H-LU seconds recorded
    path2 = tmp_path / "two_h.json"
    assert main(["bench", "two-cubes", "--divisions", "3", "--method", "hmatrix", "--eps", "1e-8",
                 "--json", str(path2)]) == 0
    rec2 = json.loads(path2.read_text())
    assert rec2["method"] == "hmatrix" and rec2["factor_s"] > 0 and rec2["eps"] == 1e-8
    assert rec2["normal_force"] == pytest.approx(rec["normal_force"], rel=1e-6)
    assert rec2["exact_residual"] <= 1e-6


def test_check_prints_what_would_be_solved(capsys, tmp_path):
    import pathlib

    ex = pathlib.Path(__file__).resolve().parents[2] / "examples" / "two_cubes_dissimilar.toml"
    assert main(["check", str(ex)]) == 0
    out = capsys.readouterr().out
    # lower cube 6x6x6 quad4: 6 n^2 + 36 n - 18 = 414 nodes; upper 5x5x5: 312
    assert "body lower: 216 quad4 elements, 414 functional nodes (1242 unknowns)" in out
    assert "body upper: 150 quad4 elements, 312 functional nodes" in out
    assert "region zmax: 69 nodes, contact surface (69 candidate nodes)" in out
    assert "36 active frame nodes" in out and "estimated peak memory" in out
    bad = tmp_path / "bad.toml"
    bad.write_text(ex.read_text().replace("poisson_ratio = 0.3", "poisson_ratio = 0.5", 1))
    assert main(["check", str(bad)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("bemcontact: error:") and "poisson_ratio" in err and len(err.splitlines()) == 1


def test_threads_1_and_2_give_identical_results(tmp_path, capsys):
    # every parallel loop writes disjoint rows and sums in a fixed order, so the
    # dense path gives the same numbers; asserted to 1e-12 relative, not bit for
    # bit, as BLAS calls on another thread count may round differently
    from bemcontact.output.read import read_csv

    src = problem(tmp_path)
    for t in ("1", "2"):
        assert main(["run", str(src), "--out", str(tmp_path / f"t{t}"), "--threads", t, "--quiet"]) == 0
    s1 = json.loads((tmp_path / "t1" / "summary.json").read_text())
    s2 = json.loads((tmp_path / "t2" / "summary.json").read_text())
    # relative to the contact force: the tangential force is zero by symmetry
    # (round-off, ~1e-13 of the normal force) and has no scale of its own
    scale = abs(s1["normal_force"])
    for key in ("normal_force", "tangential_force"):
        assert abs(s1[key] - s2[key]) <= 1e-12 * scale, (key, s1[key], s2[key])
    u_scale = max(np.abs(read_csv(tmp_path / "t1" / f"{n}_interface.csv")[c]).max()
                  for n in ("lower", "upper") for c in ("ux", "uy", "uz"))
    for name in ("frame.csv", "lower_interface.csv", "upper_interface.csv"):
        a, b = read_csv(tmp_path / "t1" / name), read_csv(tmp_path / "t2" / name)
        # each column against the scale of its quantity (tractions: the largest
        # traction component; lengths: the largest coordinate or displacement):
        # a field that is zero by symmetry (tangential tractions here) is round-off
        # displacement-level columns (u, gap, slip) against the largest interface
        # displacement of the run (frame.csv's gaps and slips are all round-off here)
        groups = [("pressure", "tx", "ty", "tz"), ("x", "y", "z"), ("ux", "uy", "uz", "gap",
                  "slip_x", "slip_y", "slip_z"), ("nx", "ny", "nz"), ("weight",), ("state",)]
        for group in groups:
            cols = [c for c in group if c in a]
            if not cols:
                continue
            scale = max(max(np.abs(a[c]).max() for c in cols), 1e-300)
            if "gap" in group:
                scale = max(scale, u_scale)
            for col in cols:
                assert np.abs(a[col] - b[col]).max() <= 1e-12 * scale, (name, col)
        assert set(a) <= {c for g in groups for c in g}, set(a)


def test_mesh_info_reports_regions_quality_and_orientation(tmp_path, capsys):
    good = tmp_path / "box.vtu"
    bc.box((0, 0, 0), (2, 1, 1), (4, 1, 2)).to_meshio().write(good)
    assert main(["mesh-info", str(good)]) == 0
    out = capsys.readouterr().out
    # 2x1x1 box, 4x1x2 elements: 2*(4*1 + 4*2 + 1*2) = 28 quads, area 2*(2 + 2 + 1) = 10
    assert f"{good}: 28 quad4 elements" in out and "area 10" in out
    # edges 0.5 (x), 1 (y), 0.5 (z): shortest 0.5, worst aspect 2
    assert "min 0.5," in out and "worst 2 " in out
    assert "shell 0: 28 elements, signed volume 2" in out and "usable as a body" in out
    bad = tmp_path / "inverted.vtu"
    bc.box(divisions=2).reversed().to_meshio().write(bad)
    assert main(["mesh-info", str(bad)]) == 2
    captured = capsys.readouterr()
    assert "signed volume -1" in captured.out
    assert captured.err.startswith("bemcontact: error:") and "inverted orientation" in captured.err
    assert main(["mesh-info", str(tmp_path / "missing.msh")]) == 2
    assert "no such file" in capsys.readouterr().err


def test_check_names_the_bodies_on_compressed_operators(tmp_path, capsys):
    """With [solver.linear] method = "hmatrix", check says which bodies use
    compressed operators (their memory is not known before the build)."""
    text = problem(tmp_path).read_text()
    p = tmp_path / "h.toml"
    p.write_text(text + '\n[solver]\nlinear = { method = "hmatrix" }\n')
    assert main(["check", str(p)]) == 0
    out = capsys.readouterr().out
    assert "compressed operators (H-matrix, H-LU) for lower, upper" in out
    assert main(["check", str(problem(tmp_path))]) == 0
    assert "compressed operators" not in capsys.readouterr().out


@pytest.mark.parametrize("where, message", [
    ("", "--out: the output directory is an empty path"),
    (".", "--out: is the current directory"),
    ("/", "--out: is a filesystem root"),
])
def test_out_places_that_are_refused(tmp_path, monkeypatch, capsys, where, message):
    """`--out ""`, `.` and `/` (which would put the run into the current
    directory or a root, replacing files there) are refused in one line
    before anything is solved."""
    src = problem(tmp_path)
    monkeypatch.chdir(tmp_path)
    (tmp_path / "summary.json").write_text("mine")
    assert main(["run", str(src), "--out", where]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and message in err, err
    assert (tmp_path / "summary.json").read_text() == "mine"


def test_out_of_other_files_is_refused_unless_forced(tmp_path, capsys):
    out = tmp_path / "mine"
    out.mkdir()
    (out / "summary.json").write_text("my summary")
    src = problem(tmp_path)
    assert main(["run", str(src), "--out", str(out), "--quiet"]) == 2
    err = capsys.readouterr().err
    assert "is not a bemcontact output directory (summary.json)" in err and "--force" in err
    assert (out / "summary.json").read_text() == "my summary"
    assert main(["run", str(src), "--out", str(out), "--quiet", "--force"]) == 0
    assert json.loads((out / "summary.json").read_text())["converged"] is True


FIGURES_SKIPPED = (
    'bemcontact: warning: figures skipped (frame_tractions.png): matplotlib is not installed; '
    'pip install "bemcontact[plot]" to draw them'
)


def _tree(directory):
    return sorted(p.relative_to(directory).as_posix() for p in directory.rglob("*"))


@pytest.mark.parametrize("flags", [["--threads", "1"], ["--quiet"]])
def test_run_without_matplotlib_skips_the_figures_with_one_warning_line(
    tmp_path, capsys, monkeypatch, flags
):
    """Figures are on by default: without matplotlib the run still succeeds,
    writes every other file (the same as with matplotlib, less the PNG) and
    says so in one line on stderr (also under --quiet)."""
    path = problem(tmp_path)
    assert main(["run", str(path), "--out", str(tmp_path / "with"), "--quiet"]) == 0
    capsys.readouterr()
    monkeypatch.setitem(sys.modules, "matplotlib", None)  # import matplotlib fails
    out = tmp_path / "without"
    code = main(["run", str(path), "--out", str(out), *flags])
    captured = capsys.readouterr()
    assert code == 0, captured.err
    assert captured.err.splitlines() == [FIGURES_SKIPPED]
    assert set(_tree(tmp_path / "with")) - set(_tree(out)) == {"frame_tractions.png"}
    assert set(_tree(out)) <= set(_tree(tmp_path / "with"))
    assert json.loads((out / "summary.json").read_text())["converged"] is True
    if "--quiet" in flags:
        assert captured.out == ""
    else:
        assert "frame_tractions.png" not in captured.out and "frame.csv" in captured.out


def test_check_without_matplotlib_warns_once(tmp_path, capsys, monkeypatch):
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    assert main(["check", str(problem(tmp_path))]) == 0
    captured = capsys.readouterr()
    assert captured.err.splitlines() == [FIGURES_SKIPPED]
    assert "valid" in captured.out


def test_figures_asked_for_without_matplotlib_is_one_error_line(tmp_path, capsys, monkeypatch):
    """`[output] figures = true` is a request: refused before the solve (exit 2,
    nothing written) rather than dropped."""
    path = problem(tmp_path)
    path.write_text(path.read_text() + "\n[output]\nfigures = true\n")
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    out = tmp_path / "out"
    assert main(["run", str(path), "--out", str(out)]) == 2
    captured = capsys.readouterr()
    assert captured.err.splitlines() == [(
        f"bemcontact: error: {path}: output.figures: needs matplotlib, which is not installed, "
        'got True; pip install "bemcontact[plot]", or set figures = false'
    )]
    assert not out.exists()


def test_gmsh_mesh_without_gmsh_is_one_error_line(capsys, monkeypatch):
    """A body meshed by gmsh from the problem file names the install command."""
    monkeypatch.setitem(sys.modules, "gmsh", None)
    example = ROOT / "examples" / "hertz_sphere_on_block.toml"
    assert main(["check", str(example)]) == 2
    captured = capsys.readouterr()
    assert captured.err.splitlines() == [(
        f"bemcontact: error: {example}: body[0].mesh.graded_box: needs gmsh to generate this "
        'mesh, which is not installed; pip install "bemcontact[gmsh]", or give the mesh as a file'
    )]
    assert captured.out == ""


def test_summary_prints_round_off_forces_as_zero_and_conditions_as_written(tmp_path, capsys):
    """The tiny problem pushes straight down: its tangential force is
    round-off (~1e-13 of the normal force), printed as 0 with the solve's
    resolution (10 x tolerance x |contact force|); a sideways push prints
    its number.  check shows conditions as the problem file writes them,
    not Python reprs."""
    src = problem(tmp_path)
    assert main(["run", str(src), "--out", str(tmp_path / "a")]) == 0
    out = capsys.readouterr().out
    s = json.loads((tmp_path / "a" / "summary.json").read_text())
    floor = 10 * 1e-10 * np.linalg.norm(s["contact_force"])
    assert abs(s["tangential_force"]) <= floor
    assert f"tangential force  0 N (below the solve's resolution, {floor:.1g} N)" in out
    side = problem(tmp_path, top="[0.002, 0, -0.04]", mu="0.5")
    assert main(["run", str(side), "--out", str(tmp_path / "b")]) == 0
    out = capsys.readouterr().out
    t = json.loads((tmp_path / "b" / "summary.json").read_text())["tangential_force"]
    assert f"tangential force  {t:.6g} N" in out and abs(t) > 1.0
    assert main(["check", str(side)]) == 0
    out = capsys.readouterr().out
    assert "region zmax: " in out and "displacement [0.002, 0, -0.04]" in out
    assert "Displacement(" not in out


# ----------------------------------------------------------------------------- out of memory


@pytest.mark.parametrize("command", ["run", "check", "mesh-info", "bench"])
def test_an_allocation_failure_is_one_line_exit_2(tmp_path, capsys, monkeypatch, command):
    """std::bad_alloc in the H-LU (MemoryError through nanobind) or a failed
    numpy allocation is one line naming the file and the memory available
    (and for run the solve's estimated peak), exit 2, no traceback, the
    output directory untouched; --debug re-raises it."""
    import bemcontact.cli as cli
    import bemcontact.mesh as mesh_package

    def no_memory(*args, **kwargs):
        raise MemoryError("std::bad_alloc")

    monkeypatch.setattr(cli, "machine_memory", lambda: (32e9, 12.5e9))
    src = problem(tmp_path)
    out = tmp_path / "out"
    if command == "run":
        assert main(["run", str(src), "--out", str(out), "--quiet"]) == 0
        before = {p: p.read_bytes() for p in out.rglob("*") if p.is_file()}
        monkeypatch.setattr(bc.ProblemFile, "solve", no_memory)
        argv = ["run", str(src), "--out", str(out)]
        name = src
    elif command == "check":
        monkeypatch.setattr(cli, "load_problem", no_memory)
        argv, name = ["check", str(src)], src
    elif command == "bench":
        import bemcontact.bench

        monkeypatch.setattr(bemcontact.bench, "one_body", no_memory)
        argv, name = ["bench", "one-body", "--nodes", "100"], "bench one-body"
    else:
        monkeypatch.setattr(mesh_package, "read_mesh", no_memory)
        name = ROOT / "tests" / "data" / "bad" / "support" / "cube_named_regions.msh"
        argv = ["mesh-info", str(name)]
    assert main(argv) == 2
    err = capsys.readouterr().err
    expected = f"bemcontact: error: {name}: out of memory (12.5 GB available of 32.0 GB)"
    assert err.startswith(expected) and err.count("\n") == 1, err
    assert err.endswith("; use a coarser mesh or a machine with more memory\n"), err
    if command == "run":
        import re

        assert re.search(r"; the solve's estimated peak memory is \d+\.\d\d GB \(at the "
                         r"(frame|condensation of (lower|upper)|newton)\);", err), err
        assert {p: p.read_bytes() for p in out.rglob("*") if p.is_file()} == before
        assert sorted(p.name for p in tmp_path.iterdir()) == ["out", "tiny.toml"]
    with pytest.raises(MemoryError):
        main([*argv, "--debug"])


def test_exit_3_into_an_earlier_run_replaces_it_whole(tmp_path, capsys):
    """A run that does not converge, written over an earlier converged one,
    replaces it whole: the directory holds the diagnostic run alone, none of
    the earlier run's VTU and CSV files beside the ``"converged": false``
    summary."""
    out = tmp_path / "out"
    assert main(["run", str(problem(tmp_path)), "--out", str(out), "--quiet"]) == 0
    assert (out / "frame.vtu").exists()
    path = problem(tmp_path, top='["free", "free", -0.04]', mu="0")
    assert main(["run", str(path), "--out", str(out)]) == 3
    capsys.readouterr()
    assert sorted(p.name for p in out.iterdir()) == [".bemcontact-run.json", "summary.json"]
    assert json.loads((out / "summary.json").read_text())["converged"] is False
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out", "tiny.toml"]


def test_check_refuses_what_run_would_refuse_for_memory(tmp_path, capsys, monkeypatch):
    """check refuses what run would refuse for memory: its report ("valid",
    the machine's memory) is followed by run's refusal in one line, exit 2;
    run refuses it before the solve, naming the file."""
    import bemcontact.cli as cli

    src = problem(tmp_path)
    assert main(["check", str(src)]) == 0
    capsys.readouterr()
    monkeypatch.setattr(cli, "machine_memory", lambda: (2e9, 1e6))  # 1 MB available
    assert main(["check", str(src)]) == 2
    out, err = capsys.readouterr()
    assert out.startswith(f"{src}: valid") and "this machine: 0.0 GB available of 2.0 GB" in out
    assert err.startswith(f"bemcontact: error: {src}: the solve needs about ") and err.endswith(
        ", more than this machine's 1 MB of available memory (run refuses it); use a coarser "
        "mesh or smaller contact surfaces\n") and err.count("\n") == 1, err
    # run refuses it before the solve, in one line that names the file too
    monkeypatch.setattr("bemcontact.contact.memory.machine_memory", lambda: (2e9, 1e6))
    out_dir = tmp_path / "out"
    assert main(["run", str(src), "--out", str(out_dir)]) == 2
    out, err = capsys.readouterr()
    assert out == "" and err.startswith(f"bemcontact: error: {src}: the solve needs about ") \
        and err.count("\n") == 1 and not out_dir.exists(), err
