"""Result files: readable with meshio / json / csv, values equal to the
result's, all-or-nothing writing; the interface line figure."""

from __future__ import annotations

import csv
import dataclasses
import json
import math
import pathlib
import sys

import meshio
import numpy as np
import pytest

import bemcontact as bc
from bemcontact.output import write as io
from bemcontact.output.read import read_csv
from bemcontact.output.plot import interface_line, plot_interface_line

FILES = [
    "summary.json", "lower.vtu", "upper.vtu", "lower_interface.vtu", "upper_interface.vtu",
    "frame.vtu", "lower.pvd", "upper.pvd", "lower_interface.pvd", "upper_interface.pvd",
    "frame.pvd", "lower_interface.csv", "upper_interface.csv", "frame.csv",
    "frame_tractions.png",
]  # fmt: skip


@pytest.fixture(scope="module")
def result():
    """A small upper block on a larger lower one: most lower interface nodes
    lie outside the upper block, so their gaps are NaN."""
    lower = bc.ElasticBody(
        bc.box((0, 0, 0), (2, 2, 2), 2), bc.LinearElastic(1e4, 0.3), {"zmin": bc.Fixed()},
        name="lower",
    )
    upper = bc.ElasticBody(
        bc.box((0.5, 0.5, 2), (1.5, 1.5, 3), 1), bc.LinearElastic(1e4, 0.3),
        {"zmax": bc.Displacement((0, 0, -0.02))}, name="upper",
    )
    r = bc.ContactProblem(lower, upper, bc.ContactPair("zmax", "zmin", 0.2)).solve(
        bc.SolverOptions(threads=1)
    )
    assert np.isnan(r.interfaces[0].gap).any()
    return r


@pytest.fixture(scope="module")
def written(result, tmp_path_factory):
    out = tmp_path_factory.mktemp("io") / "nested" / "run"
    files = io.write_results(result, out, {"file": "p.toml", "title": "t"})
    return out, files


def test_write_results_creates_the_listed_files(written):
    out, files = written
    assert [f.name for f in files] == FILES
    assert sorted(p.name for p in out.iterdir()) == sorted([*FILES, "steps", ".bemcontact-run.json"])
    assert [p.name for p in out.parent.iterdir()] == ["run"]  # no temporary left


def test_summary_json(written, result):
    out, _ = written
    s = json.loads((out / "summary.json").read_text())
    assert s["converged"] is True
    assert s["normal_force"] == result.normal_force
    assert s["tangential_force"] == result.tangential_force
    assert s["newton_iterations"] == result.newton_iterations
    assert s["names"] == ["lower", "upper"]
    assert s["version"] == bc.__version__
    import platform

    assert s["versions"]["bemcontact"] == bc.__version__
    assert s["versions"]["numpy"] == np.__version__
    assert s["versions"]["python"] == platform.python_version()
    assert s["problem"] == {"file": "p.toml", "title": "t"}
    assert s["states"]["upper"] == result.interfaces[1].counts()


def test_body_vtu_is_the_mesh_without_holes_with_region_names(written, result):
    """Points are the mesh nodes and cells the mesh elements (shared nodes:
    no gaps along edges); continuous nodes carry their values as computed;
    the region names round-trip through meshio as field data."""
    out, _ = written
    s = json.loads((out / "summary.json").read_text())
    for sol, name in zip(result.bodies, result.names):
        m = meshio.read(out / f"{name}.vtu")
        d = sol.discretization
        np.testing.assert_array_equal(m.points, d.mesh.nodes)
        (cells,) = m.cells
        assert cells.type == "quad"
        np.testing.assert_array_equal(cells.data, d.mesh.elements)
        np.testing.assert_array_equal(m.cell_data["region"][0], d.mesh.element_region)
        names = {k: v.ravel().tolist() for k, v in m.field_data.items()}
        assert names == {n: [i, 2] for i, n in enumerate(d.mesh.region_names)}
        assert s["regions"][name] == list(d.mesh.region_names) == [
            "xmin", "xmax", "ymin", "ymax", "zmin", "zmax"]
        shared = d.element < 0
        assert shared.sum() == {"lower": 6, "upper": 0}[name]  # face centres
        assert (~shared).sum() > 0
        g = d.geometric_node[shared]
        np.testing.assert_allclose(m.point_data["displacement"][g], sol.displacement[shared],
                                   rtol=1e-12, atol=1e-15)
        np.testing.assert_allclose(m.point_data["traction"][g], sol.traction[shared],
                                   rtol=1e-12, atol=1e-12)
        # the copies of a node share its area: the weights still sum to the area
        assert m.point_data["weight"].sum() == pytest.approx(d.mesh.area, rel=1e-12)
        assert np.linalg.norm(m.point_data["normal"], axis=1) == pytest.approx(1.0)


@pytest.mark.parametrize("etype", ["tri3", "quad4", "tri6", "quad8", "quad9"])
def test_geometric_values_are_exact_for_linear_fields(etype):
    """An element's interpolant through its shifted edge and corner nodes is
    exact for a linear field, so the value at every mesh node is too."""
    from bemcontact.bem.discretization import discretize
    from bemcontact.output.vtu import geometric_values

    d = discretize(bc.box((0, 0, 0), (1, 2, 3), 2, etype))
    assert (d.element >= 0).sum() > 0
    A = np.array([[1.0, -2.0, 0.5], [0.3, 0.0, 4.0]])
    nodes, v = geometric_values(d, d.points @ A.T + [1.0, -1.0])
    np.testing.assert_array_equal(nodes, np.arange(d.mesh.n_nodes))
    np.testing.assert_allclose(v, d.mesh.nodes @ A.T + [1.0, -1.0], rtol=0, atol=1e-12)
    state = (d.element >= 0).astype(np.int8)  # 1 at the discontinuous copies
    nodes, top = geometric_values(d, state, how="max")
    assert set(nodes[top == 1]) == set(d.geometric_node[d.element >= 0])
    _, w = geometric_values(d, d.weights, how="sum")
    assert w.sum() == pytest.approx(d.weights.sum(), rel=1e-14)


def test_interface_vtu_and_csv(written, result):
    out, _ = written
    checked = []
    for sol, iface in zip(result.bodies, result.interfaces):
        m = meshio.read(out / f"{iface.body}_interface.vtu")
        mesh = sol.discretization.mesh
        elements = mesh.region(iface.surface)
        nodes = np.unique(mesh.elements[elements])
        np.testing.assert_array_equal(m.points, mesh.nodes[nodes])  # the true geometry
        assert m.cells[0].data.shape[0] == elements.size
        np.testing.assert_array_equal(nodes[m.cells[0].data], mesh.elements[elements])
        at = {n: i for i, n in enumerate(nodes)}
        shared = sol.discretization.element[iface.nodes] < 0
        rows = [at[g] for g in sol.discretization.geometric_node[iface.nodes[shared]]]
        for key in ("pressure", "tangential_traction", "displacement", "traction"):
            np.testing.assert_allclose(m.point_data[key][rows], getattr(iface, key)[shared],
                                       rtol=1e-12, atol=1e-9, err_msg=key)
        np.testing.assert_array_equal(m.point_data["state"][rows], iface.state[shared])
        checked.append(len(rows))
        assert {k: v.ravel().tolist() for k, v in m.field_data.items()}[iface.surface] == [
            mesh.region_names.index(iface.surface), 2]
        with open(out / f"{iface.body}_interface.csv", newline="") as f:
            rows = list(csv.reader(f))
        assert rows[0] == list(io.INTERFACE_COLUMNS)
        header = "x,y,z,pressure,tx,ty,tz,gap,slip_x,slip_y,slip_z,state,ux,uy,uz"
        assert rows[0] == header.split(",")
        data = np.array(rows[1:], dtype=float)
        expected = np.column_stack([
            iface.points, iface.pressure, iface.tangential_traction, iface.gap, iface.slip,
            iface.state, iface.displacement,
        ])  # fmt: skip
        np.testing.assert_array_equal(data, expected)  # NaN gaps stay NaN, full precision
        assert all(r[11] in ("0", "1", "2") for r in rows[1:])
    assert checked == [1, 0]  # the centre of the lower block's top face


def test_frame_vtu_and_csv(written, result):
    out, _ = written
    fr = result.frame
    m = meshio.read(out / "frame.vtu")
    np.testing.assert_array_equal(m.points, fr.points)
    assert m.cells[0].type == "quad"  # the frame's own elements were recovered
    for key in ("pressure", "tangential_traction", "gap", "slip", "state"):
        np.testing.assert_array_equal(m.point_data[key], getattr(fr, key), err_msg=key)
    c = read_csv(out / "frame.csv")
    assert list(c) == list(io.FRAME_COLUMNS)
    np.testing.assert_array_equal(c["pressure"], fr.pressure)
    t = np.column_stack([c["tx"], c["ty"], c["tz"]])
    np.testing.assert_array_equal(t, fr.tangential_traction)
    np.testing.assert_array_equal(c["state"], fr.state)
    assert c["weight"] @ c["pressure"] == pytest.approx(result.normal_force, rel=1e-12)


def test_failed_write_leaves_nothing(result, tmp_path, monkeypatch):
    def boom(*args, **kwargs):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(io, "_write_frame_csv", boom)
    out = tmp_path / "a" / "b" / "out"
    with pytest.raises(OSError, match="No space left"):
        io.write_results(result, out)
    assert list(tmp_path.iterdir()) == []  # not even the parents this call created

    monkeypatch.undo()
    existing = tmp_path / "existing"
    io.write_results(result, existing, options=io.OutputOptions(figures=False))
    before = {p: p.read_bytes() for p in existing.rglob("*") if p.is_file()}
    monkeypatch.setattr(io, "_write_frame_csv", boom)
    with pytest.raises(OSError):
        io.write_results(result, existing)
    assert [p.name for p in tmp_path.iterdir()] == ["existing"]  # no lock, .tmp or .old left
    assert {p: p.read_bytes() for p in existing.rglob("*") if p.is_file()} == before


def test_a_directory_bemcontact_did_not_write_is_refused_unless_forced(result, tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    (out / "summary.json").write_text("old")
    (out / "notes.txt").write_text("mine")
    with pytest.raises(bc.ConfigError, match="is not a bemcontact output directory "
                       r"\(notes.txt and more\); name a new directory, or pass --force"):
        io.write_results(result, out)
    assert (out / "summary.json").read_text() == "old"
    # forced: the results are moved in beside the user's file, nothing else touched
    io.write_results(result, out, force=True)
    assert json.loads((out / "summary.json").read_text())["converged"] is True
    assert (out / "notes.txt").read_text() == "mine"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"]


def test_out_dir_that_is_a_file(result, tmp_path):
    f = tmp_path / "file"
    f.write_text("x")
    with pytest.raises(bc.ConfigError, match="exists and is not a directory"):
        io.write_results(result, f)
    assert f.read_text() == "x" and [p.name for p in tmp_path.iterdir()] == ["file"]


def test_body_names_that_cannot_name_files(result, tmp_path):
    bad = dataclasses.replace(result, names=("../up", "lower"))
    with pytest.raises(bc.ConfigError, match=r"body name '\.\./up' cannot name a file"):
        io.write_results(bad, tmp_path / "out")
    clash = dataclasses.replace(result, names=("frame", "lower"))
    with pytest.raises(bc.ConfigError, match="clashing file names"):
        io.write_results(clash, tmp_path / "out")
    assert list(tmp_path.iterdir()) == []


def test_write_summary_of_a_failure_is_strict_json(result, tmp_path):
    failed = dataclasses.replace(result, converged=False)
    path = io.write_summary(failed, tmp_path / "out", {"file": "p.toml"}, error="did not converge")
    s = json.loads(path.read_text())
    assert s["converged"] is False and s["error"] == "did not converge"
    assert s["normal_force"] == result.normal_force
    path = io.write_summary({"converged": False, "residual": math.nan}, tmp_path / "out2")
    text = path.read_text()
    assert "NaN" not in text and json.loads(text)["residual"] is None


def test_interface_line_from_result_equals_from_directory(written, result):
    out, _ = written
    a = interface_line(result)
    b = interface_line(out)
    assert [x.body for x in a] == ["lower", "upper"]
    for x, y in zip(a, b):
        assert (x.axis, x.across, x.row) == (0, 1, y.row) and x.across == y.across
        np.testing.assert_array_equal(x.coordinate, y.coordinate)
        np.testing.assert_array_equal(x.displacement, y.displacement)
        assert np.all(np.diff(x.coordinate) > 0) and x.coordinate.size >= 2
    with pytest.raises(bc.ConfigError, match="normal to the contact interface"):
        interface_line(result, axis=2)


def test_plot_interface_line_writes_a_png(written, result, tmp_path):
    out, _ = written
    png = plot_interface_line({"from memory": result, "from disk": out}, tmp_path / "f.png")
    assert png == tmp_path / "f.png"
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


# ------------------------------------------------------------ load-step series and options


def test_pvd_collections_list_one_vtu_per_load_step(written, result):
    """Each VTU series has a PVD collection whose data sets are the per-step
    files, in order, and the last step's file equals the final-state file."""
    import xml.etree.ElementTree as ET

    import meshio

    out, _ = written
    n = len(result.history)
    assert n >= 1
    for name in ("lower", "upper_interface", "frame"):
        root = ET.parse(out / f"{name}.pvd").getroot()
        assert root.get("type") == "Collection"
        sets = root.find("Collection").findall("DataSet")
        assert [float(d.get("timestep")) for d in sets] == list(range(1, n + 1))
        files = [d.get("file") for d in sets]
        assert all((out / f).is_file() for f in files)
        last = meshio.read(out / files[-1])
        final = meshio.read(out / f"{name}.vtu")
        for key in final.point_data:
            np.testing.assert_array_equal(last.point_data[key], final.point_data[key])


def test_steps_of_a_history_are_written_per_step(tmp_path):
    """A two-step history (displacement 0.01 then 0.02): two numbered files
    per series whose frame pressures differ, the second equal to the final."""
    import meshio

    lower = bc.ElasticBody(
        bc.box((0, 0, 0), (1, 1, 1), 2), bc.LinearElastic(1e4, 0.3), {"zmin": bc.Fixed()},
        name="lower",
    )
    upper = bc.ElasticBody(
        bc.box((0, 0, 1), (1, 1, 2), 2), bc.LinearElastic(1e4, 0.3),
        {"zmax": bc.Displacement((0, 0, -0.01))}, name="upper",
    )
    steps = [
        bc.LoadStep({}, 1, "half"),
        bc.LoadStep({"upper": {"zmax": [bc.Displacement((0, 0, -0.02))]}}, 1, "full"),
    ]
    r = bc.ContactProblem(lower, upper, bc.ContactPair("zmax", "zmin")).solve(
        bc.SolverOptions(threads=1), steps=steps
    )
    io.write_results(r, tmp_path / "out", options=io.OutputOptions(figures=False, csv=False))
    out = tmp_path / "out"
    p1 = meshio.read(out / "steps" / "frame_001.vtu").point_data["pressure"]
    p2 = meshio.read(out / "steps" / "frame_002.vtu").point_data["pressure"]
    # linear elastic, full contact: the second step's pressure is twice the first
    np.testing.assert_allclose(p2, 2 * p1, rtol=1e-8, atol=1e-12 * np.abs(p2).max())
    np.testing.assert_array_equal(meshio.read(out / "frame.vtu").point_data["pressure"], p2)
    assert not list(out.glob("*.csv")) and not list(out.glob("*.png"))


def test_rewrite_replaces_an_earlier_run_whole(result, tmp_path):
    out = tmp_path / "out"
    io.write_results(result, out, options=io.OutputOptions(figures=False))
    assert (out / "steps").is_dir()
    io.write_results(result, out, options=io.OutputOptions(figures=False, vtu=False))
    # the earlier run's files are gone (they were bemcontact's), the new run is whole
    assert sorted(p.name for p in out.iterdir()) == sorted(
        [".bemcontact-run.json", "summary.json", "frame.csv",
         *(f"{n}_interface.csv" for n in result.names)])
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"]  # no .old/.tmp/.lock left


def test_a_user_file_in_a_run_directory_is_never_deleted(result, tmp_path):
    """A rewrite of a run directory whose steps/ holds a user's file (which
    replacing steps/ whole would delete) is refused, naming the file; with
    force the file stays."""
    out = tmp_path / "out"
    io.write_results(result, out, options=io.OutputOptions(figures=False))
    (out / "steps" / "my_notes.txt").write_text("mine")
    with pytest.raises(bc.ConfigError, match=r"holds files bemcontact did not write "
                       r"\(steps/my_notes.txt\)"):
        io.write_results(result, out, options=io.OutputOptions(figures=False))
    io.write_results(result, out, options=io.OutputOptions(figures=False), force=True)
    assert (out / "steps" / "my_notes.txt").read_text() == "mine"


def test_output_options_last_only_and_validation(result, tmp_path):
    files = io.write_results(
        result, tmp_path / "o", options=io.OutputOptions(steps="last", csv=False, figures=False)
    )
    assert sorted(f.name for f in files) == sorted(
        ["summary.json", "lower.vtu", "upper.vtu", "lower_interface.vtu", "upper_interface.vtu",
         "frame.vtu"]
    )
    assert not (tmp_path / "o" / "steps").exists()
    with pytest.raises(bc.ConfigError, match="OutputOptions.steps must be 'all' or 'last'"):
        io.OutputOptions(steps="every")
    with pytest.raises(bc.ConfigError, match="OutputOptions.vtu must be True or False"):
        io.OutputOptions(vtu=1)


def test_without_matplotlib_default_figures_are_skipped_asked_for_refused(
    result, tmp_path, monkeypatch
):
    """write_results without options writes everything else and warns; an
    explicit OutputOptions(figures=True) is an error, nothing written."""
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    with pytest.warns(bc.OptionalDependencyWarning, match=r"figures skipped") as w:
        files = io.write_results(result, tmp_path / "o")
    assert len(w) == 1
    assert [f.name for f in files] == FILES[:-1]
    assert sorted(p.name for p in (tmp_path / "o").iterdir()) == sorted(
        [*FILES[:-1], "steps", ".bemcontact-run.json"]
    )
    with pytest.raises(bc.ConfigError, match=r'needs matplotlib.*pip install "bemcontact\[plot\]"'):
        io.write_results(result, tmp_path / "p", options=io.OutputOptions(figures=True))
    assert not (tmp_path / "p").exists()


def test_frame_tractions_png(written):
    from PIL import Image

    out, _ = written
    with Image.open(out / "frame_tractions.png") as img:
        assert img.format == "PNG" and img.size[0] > 1000


def test_summary_records_provenance(written, result):
    """summary.json says where and how the run was made: platform, CPU,
    cores, the compiled core's build, the threads of the solve and the
    versions of the optional libraries it used."""
    from bemcontact._native import core
    from bemcontact.linalg.threads import available_cores

    s = json.loads((written[0] / "summary.json").read_text())
    p = s["provenance"]
    assert p["cores"] == available_cores() and p["cpu"] and p["platform"]
    assert p["build"]["native"] == core().build_info()["native"]
    assert "commit" not in p or len(p["commit"].split("-")[0]) == 40
    assert s["threads"] == result.threads >= 1
    if "matplotlib" in sys.modules:
        assert s["versions"]["matplotlib"] == sys.modules["matplotlib"].__version__


def test_problem_file_and_mesh_hashes(tmp_path):
    """The problem echo holds the SHA-256 of the problem file and of each
    mesh file it names (by the name it gives); a changed mesh changes it."""
    import hashlib
    import shutil

    from bemcontact.problemfile.reader import load_problem

    root = pathlib.Path(__file__).resolve().parents[3] / "examples"
    shutil.copy(root / "block_from_mesh_file.toml", tmp_path)
    shutil.copytree(root / "meshes", tmp_path / "meshes")
    src = tmp_path / "block_from_mesh_file.toml"
    h = load_problem(src, check_overlap=False).echo["sha256"]
    mesh = tmp_path / "meshes" / "block.msh"
    assert h == {"problem": hashlib.sha256(src.read_bytes()).hexdigest(),
                 "meshes/block.msh": hashlib.sha256(mesh.read_bytes()).hexdigest()}
    mesh.write_bytes(mesh.read_bytes() + b"\n")
    assert load_problem(src, check_overlap=False).echo["sha256"]["meshes/block.msh"] != \
        h["meshes/block.msh"]
