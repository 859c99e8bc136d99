"""The bad-input corpus tests/data/bad: every malformed problem file and mesh
gives exit code 2, exactly one stderr line ``bemcontact: error: ...`` naming
the file, no traceback, and leaves ``--out DIR`` untouched.

Layout of tests/data/bad:

* ``*.toml``: problem files, each starting with ``# expect: <what is wrong>``.
  They run through ``bemcontact run PROBLEM --out DIR`` and ``bemcontact check
  PROBLEM``. ``problem_is_a_directory.toml`` is a directory.
* every other file is a broken mesh (``.msh``, ``.vtu``, ``.obj``, ``.stl``,
  ``.off``, ...): it runs through ``bemcontact mesh-info MESH`` and through the
  problem file ``uses_<mesh name with . as _>.toml``, whose body[0] reads it.
* ``support/`` holds valid meshes that bad problem files use (it is not part
  of the corpus: ``mesh-info`` accepts them).

The commands run in-process (``cli.main``) for speed; one test runs a few of
them as real processes, where no pytest warning filter or capture applies.
"""

from __future__ import annotations

import os
import pathlib
import re
import subprocess
import sys
import traceback

import pytest

from bemcontact.cli import main

BAD = pathlib.Path(__file__).resolve().parents[2] / "data" / "bad"
SUPPORT = "support"
CORPUS = sorted(p for p in BAD.iterdir() if p.name != SUPPORT)
PROBLEMS = [p for p in CORPUS if p.suffix == ".toml"]
MESHES = [p for p in CORPUS if p.suffix != ".toml"]
PREFIX = "bemcontact: error: "


def _ids(paths):
    return [p.name for p in paths]


def _uses(mesh: pathlib.Path) -> pathlib.Path:
    return BAD / f"uses_{mesh.name.replace('.', '_')}.toml"


def _mesh_named_by(problem: pathlib.Path) -> str | None:
    """The corpus mesh a ``uses_*.toml`` problem file reads (None for others)."""
    for mesh in MESHES:
        if _uses(mesh) == problem:
            return mesh.name
    return None


def _call(argv: list[str], capsys) -> tuple[int, str, str]:
    """cli.main(argv) -> (exit code, stdout, stderr); an exception escaping
    main is a test failure that shows the exception and the command."""
    try:
        code = main(argv)
    except BaseException as exc:  # noqa: BLE001 - SystemExit and KeyboardInterrupt included
        captured = capsys.readouterr()
        pytest.fail(
            f"bemcontact {' '.join(argv)} raised {type(exc).__name__}: {exc}\n"
            f"stdout: {captured.out!r}\nstderr: {captured.err!r}\n"
            + "".join(traceback.format_exception(exc)),
            pytrace=False,
        )
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def _assert_one_error_line(argv, code, out, err, *names):
    where = f"bemcontact {' '.join(argv)}\nexit code {code}\nstdout: {out!r}\nstderr: {err!r}"
    assert "Traceback" not in out and "Traceback" not in err, where
    assert code == 2, where
    lines = err.splitlines()
    assert len(lines) == 1, where
    assert err.endswith("\n"), where
    assert lines[0].startswith(PREFIX), where
    for name in names:
        assert name in lines[0], f"{name!r} not named in the error line\n{where}"


def _tree(root: pathlib.Path) -> dict[str, tuple]:
    """Every entry below root (and root): relative path -> kind, bytes, mode, mtime."""
    out = {}
    for p in [root, *sorted(root.rglob("*"))]:
        st = p.lstat()
        data = p.read_bytes() if p.is_file() else None
        out[str(p.relative_to(root))] = (p.is_dir(), data, st.st_mode, st.st_mtime_ns)
    return out


# ----------------------------------------------------------------------------- the corpus


def test_corpus_is_large_and_documented():
    assert len(CORPUS) >= 50, len(CORPUS)
    assert len(PROBLEMS) >= 40 and len(MESHES) >= 15, (len(PROBLEMS), len(MESHES))
    for p in PROBLEMS:
        if p.is_dir():
            continue
        first = p.read_bytes().split(b"\n", 1)[0]
        assert re.match(rb"^# expect: \S", first), f"{p.name}: first line {first!r}"
    for mesh in MESHES:
        assert mesh.is_file(), mesh
        problem = _uses(mesh)
        assert problem.is_file(), f"no problem file uses {mesh.name} (expected {problem.name})"
        assert f'file = "{mesh.name}"' in problem.read_text(), problem.name


def test_corpus_covers_every_mesh_format():
    suffixes = {p.suffix for p in MESHES}
    assert {".msh", ".vtu", ".obj", ".stl", ".off"} <= suffixes, suffixes
    assert any(p.stat().st_size == 0 for p in MESHES), "an empty mesh file"
    versions = {p.read_bytes()[:30].split(b"\n")[1] for p in MESHES
                if p.suffix == ".msh" and p.read_bytes().startswith(b"$MeshFormat")}
    assert {b"2.2 0 8", b"4.1 0 8"} <= versions, versions


# ----------------------------------------------------------------------------- run / check


@pytest.mark.parametrize("path", PROBLEMS, ids=_ids(PROBLEMS))
def test_run_bad_problem_exit_2_one_line_nothing_written(path, tmp_path, capsys):
    out = tmp_path / "out"
    argv = ["run", str(path), "--out", str(out)]
    code, stdout, stderr = _call(argv, capsys)
    mesh = _mesh_named_by(path)
    _assert_one_error_line(argv, code, stdout, stderr, path.name, *([mesh] if mesh else []))
    assert stdout == "", stdout
    assert not out.exists(), f"{argv}: --out directory created: {sorted(out.rglob('*'))}"
    assert list(tmp_path.iterdir()) == [], f"{argv}: wrote {list(tmp_path.iterdir())}"


@pytest.mark.parametrize("path", PROBLEMS, ids=_ids(PROBLEMS))
def test_check_bad_problem_exit_2_one_line(path, capsys):
    argv = ["check", str(path)]
    code, stdout, stderr = _call(argv, capsys)
    mesh = _mesh_named_by(path)
    _assert_one_error_line(argv, code, stdout, stderr, path.name, *([mesh] if mesh else []))
    assert stdout == "", stdout


@pytest.mark.parametrize("path", MESHES, ids=_ids(MESHES))
def test_mesh_info_bad_mesh_exit_2_one_line(path, capsys):
    argv = ["mesh-info", str(path)]
    code, stdout, stderr = _call(argv, capsys)
    _assert_one_error_line(argv, code, stdout, stderr, path.name)


PRE_EXISTING = [
    "material_poisson_half.toml",
    "contact_surfaces_far_apart.toml",
    "uses_mesh_inverted_normals_msh.toml",
    "syntax_invalid_toml.toml",
    "encoding_latin1.toml",
    "solver_threads_huge.toml",
]


@pytest.mark.parametrize("name", PRE_EXISTING)
def test_run_leaves_an_existing_out_dir_byte_identical(name, tmp_path, capsys):
    out = tmp_path / "out"
    (out / "old").mkdir(parents=True)
    (out / "marker.txt").write_bytes(b"results of an earlier run\n")
    (out / "summary.json").write_text('{"converged": true}\n')
    (out / "old" / "frame.csv").write_bytes(bytes(range(256)))
    os.utime(out / "marker.txt", ns=(1_000_000_000, 1_000_000_000))
    # an earlier run of bemcontact's: its manifest lists its files
    (out / ".bemcontact-run.json").write_text(
        '{"bemcontact": "0.1.0", "files": ["marker.txt", "old/frame.csv", "summary.json"]}\n')
    before = _tree(tmp_path)
    argv = ["run", str(BAD / name), "--out", str(out)]
    code, stdout, stderr = _call(argv, capsys)
    _assert_one_error_line(argv, code, stdout, stderr, name)
    assert _tree(tmp_path) == before


# ----------------------------------------------------------------------------- not in the corpus


def test_problem_file_that_does_not_exist(capsys, tmp_path):
    missing = BAD / "no_such_problem.toml"
    assert not missing.exists()
    argv = ["check", str(missing)]
    code, out, err = _call(argv, capsys)
    _assert_one_error_line(argv, code, out, err, missing.name)
    out_dir = tmp_path / "out"
    argv = ["run", str(missing), "--out", str(out_dir)]
    code, out, err = _call(argv, capsys)
    _assert_one_error_line(argv, code, out, err, missing.name)
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize(
    "target", ["support", "no_such_mesh.msh", "empty_problem.toml"],
    ids=["directory", "missing", "problem-file"],
)
def test_mesh_info_on_what_is_not_a_mesh_file(target, capsys):
    argv = ["mesh-info", str(BAD / target)]
    code, out, err = _call(argv, capsys)
    _assert_one_error_line(argv, code, out, err, target)


# ----------------------------------------------------------------------------- real processes

SUBPROCESS_CASES = [
    ("check", "encoding_latin1.toml"),
    ("check", "material_youngs_huge_integer.toml"),
    ("check", "box_coordinates_overflow.toml"),
    ("check", "box_lower_huge.toml"),
    ("run", "uses_mesh_degenerate_triangle_stl.toml"),
    ("run", "solver_threads_huge.toml"),
    ("mesh-info", "mesh_single_triangle.stl"),
    ("mesh-info", "mesh_binary_garbage.msh"),
    ("mesh-info", "mesh_huge_coordinates.off"),
]


def test_no_traceback_reaches_a_terminal(tmp_path):
    """``python -m bemcontact`` as a user runs it (default warning filters, real
    stderr): one error line, exit 2, no traceback, for a few of the corpus."""
    env = {k: v for k, v in os.environ.items() if not k.startswith("PYTEST")}
    env.pop("PYTHONWARNINGS", None)
    env.setdefault("OMP_NUM_THREADS", "1")
    failures = []
    for i, (command, name) in enumerate(SUBPROCESS_CASES):
        out = tmp_path / f"out{i}"
        argv = [command, str(BAD / name)] + (["--out", str(out)] if command == "run" else [])
        proc = subprocess.run(
            [sys.executable, "-m", "bemcontact", *argv], capture_output=True, text=True,
            env=env, cwd=tmp_path, timeout=120,
        )
        lines = proc.stderr.splitlines()
        ok = (
            proc.returncode == 2
            and len(lines) == 1
            and lines[0].startswith(PREFIX)
            and name in lines[0]
            and "Traceback" not in proc.stdout + proc.stderr
            and (command == "mesh-info" or proc.stdout == "")
            and not out.exists()
        )
        if not ok:
            failures.append(
                f"$ python -m bemcontact {' '.join(argv)}\nexit code {proc.returncode}\n"
                f"stdout:\n{proc.stdout}\nstderr:\n{proc.stderr}"
            )
    assert not failures, "\n\n".join(failures)
    assert sorted(p.name for p in tmp_path.iterdir()) == []
