"""Result files of an assembly (several bodies and contact pairs): every
body's surface, per pair its frame, interfaces and figures under the pair's
names (bemcontact.output.layout), summary.json with the pairs' forces; a
two-body run keeps its plain file names (no pair prefix, no pairs in
summary.json)."""

from __future__ import annotations

import dataclasses
import json

import meshio
import numpy as np
import pytest

import bemcontact as bc
from bemcontact import ContactPair, ContactProblem, Displacement, ElasticBody, LinearElastic, box
from bemcontact.output import write as io
from bemcontact.output.layout import layout, pair_stems
from bemcontact.output.plot import frame_tractions_figure, interface_line
from bemcontact.output.read import read_csv

ROLLERS = {"xmin": Displacement((0.0, None, None)), "ymin": Displacement((None, 0.0, None))}
PAIRS = ("bottom+middle", "middle+top")
#: the stems of an assembly's files, in the listing's order
SERIES = [
    "bottom", "middle", "top",
    "bottom+middle_bottom_interface", "bottom+middle_middle_interface", "bottom+middle_frame",
    "middle+top_middle_interface", "middle+top_top_interface", "middle+top_frame",
]  # fmt: skip
CSV = SERIES[3:]
FILES = ["summary.json", *(f"{s}.vtu" for s in SERIES), *(f"{s}.pvd" for s in SERIES),
         *(f"{s}.csv" for s in CSV), *(f"{p}_frame_tractions.png" for p in PAIRS)]


def _stack(top_load=10.0):
    """Three blocks stacked on non-matching meshes (a patch test: uniform
    pressure through both contacts), on rollers, the load on top."""
    mats = [LinearElastic(1.0e4, 0.3), LinearElastic(3.0e4, 0.2), LinearElastic(2.0e4, 0.25)]
    meshes = [box((0, 0, z), (2, 2, z + 1), (n, n, 2), element_type=t)
              for z, n, t in ((0, 3, "quad4"), (1, 4, "quad4"), (2, 2, "tri3"))]
    bodies = [
        ElasticBody(meshes[0], mats[0], {"zmin": Displacement((None, None, 0.0)), **ROLLERS},
                    name="bottom"),
        ElasticBody(meshes[1], mats[1], dict(ROLLERS), name="middle"),
        ElasticBody(meshes[2], mats[2], {"zmax": bc.Pressure(top_load), **ROLLERS}, name="top"),
    ]
    pairs = [ContactPair("zmax", "zmin", bodies=("bottom", "middle"), frame_on="coarser"),
             ContactPair("zmax", "zmin", bodies=("middle", "top"), frame_on="coarser")]
    return ContactProblem(bodies=bodies, pairs=pairs)


@pytest.fixture(scope="module")
def result():
    """Two load steps: pressure 5, then 10 on top."""
    steps = [bc.LoadStep({"top": {"zmax": [bc.Pressure(5.0)]}}, 1, "half"),
             bc.LoadStep({"top": {"zmax": [bc.Pressure(10.0)]}}, 1, "full")]
    r = _stack().solve(bc.SolverOptions(threads=1), steps=steps)
    assert r.converged and len(r.pairs) == 2 and len(r.history) == 2
    return r


@pytest.fixture(scope="module")
def written(result, tmp_path_factory):
    out = tmp_path_factory.mktemp("asm") / "run"
    files = io.write_results(result, out, {"file": "p.toml", "units": {"force": "N"}})
    return out, files


def test_an_assembly_writes_each_body_and_each_pairs_files(written):
    out, files = written
    assert [f.name for f in files] == FILES
    steps = sorted(f"steps/{s}_{k:03d}.vtu" for s in SERIES for k in (1, 2))
    listed = sorted(p.relative_to(out).as_posix() for p in out.rglob("*") if p.is_file())
    assert listed == sorted([*FILES, *steps, ".bemcontact-run.json"])
    manifest = json.loads((out / ".bemcontact-run.json").read_text())["files"]
    assert manifest == sorted([*FILES, *steps])
    assert [p.name for p in out.parent.iterdir()] == ["run"]  # no temporary left
    pvd = (out / "middle+top_frame.pvd").read_text()
    assert 'file="steps/middle+top_frame_001.vtu"' in pvd
    assert 'timestep="2" group="" part="0" file="steps/middle+top_frame_002.vtu"' in pvd


def test_each_pairs_frame_files_hold_that_pairs_frame(written, result):
    out, _ = written
    for stem, pair in zip(PAIRS, result.pairs):
        m = meshio.read(out / f"{stem}_frame.vtu")
        np.testing.assert_array_equal(m.points, pair.frame.points)
        np.testing.assert_array_equal(m.point_data["pressure"], pair.frame.pressure)
        np.testing.assert_array_equal(m.point_data["tangential_traction"],
                                      pair.frame.tangential_traction)
        assert m.cells[0].type in ("quad", "triangle")  # the frame's elements, not vertices
        c = read_csv(out / f"{stem}_frame.csv")
        np.testing.assert_array_equal(c["pressure"], pair.frame.pressure)
        np.testing.assert_array_equal(c["z"], pair.frame.points[:, 2])
        assert c["weight"] @ c["pressure"] == pytest.approx(pair.normal_force, rel=1e-12)
        for k, state in enumerate(result.history, start=1):  # each load step's
            s = meshio.read(out / "steps" / f"{stem}_frame_{k:03d}.vtu")
            np.testing.assert_array_equal(s.point_data["pressure"],
                                          state.pairs[result.pairs.index(pair)].frame.pressure)
    # the two frames are different (z = 1 and z = 2; 16 and 9 nodes), the steps 5 and 10
    z = [meshio.read(out / f"{s}_frame.vtu").points[:, 2] for s in PAIRS]
    assert np.all(z[0] == 1.0) and np.all(z[1] == 2.0) and z[0].size != z[1].size
    p1 = meshio.read(out / "steps" / "bottom+middle_frame_001.vtu").point_data["pressure"]
    np.testing.assert_allclose(p1, 5.0, rtol=1e-8)


def test_each_side_of_each_pair_has_its_interface(written, result):
    out, _ = written
    for stem, pair in zip(PAIRS, result.pairs):
        for iface in pair.interfaces:
            c = read_csv(out / f"{stem}_{iface.body}_interface.csv")
            np.testing.assert_array_equal(c["pressure"], iface.pressure)
            np.testing.assert_array_equal(c["uz"], iface.displacement[:, 2])
            m = meshio.read(out / f"{stem}_{iface.body}_interface.vtu")
            assert iface.surface in m.field_data
    # the middle block's two interfaces are its two faces
    lo = read_csv(out / "bottom+middle_middle_interface.csv")
    hi = read_csv(out / "middle+top_middle_interface.csv")
    assert np.allclose(lo["z"], 1.0, rtol=0, atol=1e-12)
    assert np.allclose(hi["z"], 2.0, rtol=0, atol=1e-12)
    for name, sol in zip(result.names, result.bodies):
        m = meshio.read(out / f"{name}.vtu")
        assert m.points.shape[0] == sol.discretization.mesh.n_nodes


def test_summary_has_every_body_and_each_pairs_forces(written, result):
    out, _ = written
    s = json.loads((out / "summary.json").read_text())
    assert s["names"] == ["bottom", "middle", "top"]
    assert sorted(s["regions"]) == ["bottom", "middle", "top"]
    assert [p["files"] for p in s["pairs"]] == list(PAIRS)
    assert [p["label"] for p in s["pairs"]] == [p.label for p in result.pairs]
    for e, pair in zip(s["pairs"], result.pairs):
        assert e["bodies"] == list(pair.names) and e["surfaces"] == list(pair.surfaces)
        assert e["normal_force"] == pair.normal_force
        assert e["tangential_force"] == pair.tangential_force
        assert e["contact_force"] == [float(c) for c in pair.contact_force]
        assert e["states"]["frame"] == pair.frame.counts()
        for iface in pair.interfaces:
            assert e["states"][iface.body] == iface.counts()
    # the top level is the first pair's, as in ContactResult
    assert s["normal_force"] == result.pairs[0].normal_force
    assert [h["pairs"][1]["normal_force"] for h in s["history"]] == [
        h.pairs[1].normal_force for h in result.history]


def test_figures_per_pair_name_the_pair(written, result):
    pytest.importorskip("matplotlib")
    out, _ = written
    for stem in PAIRS:
        assert (out / f"{stem}_frame_tractions.png").read_bytes()[:4] == b"\x89PNG"
    fig = frame_tractions_figure(result.pairs[1], force_unit="N")
    title = fig._suptitle.get_text()
    assert title.startswith("contact frame middle:zmax/top:zmin: normal force 40 N"), title


def test_interface_line_of_an_assembly_directory_is_its_first_pairs(written, result):
    out, _ = written
    a, b = interface_line(result), interface_line(out)
    assert [x.body for x in b] == ["bottom", "middle"]
    for x, y in zip(a, b):
        np.testing.assert_array_equal(x.displacement, y.displacement)


def test_options_select_an_assemblys_files(result, tmp_path):
    files = io.write_results(result, tmp_path / "o",
                             options=io.OutputOptions(steps="last", figures=False, vtu=False))
    assert [f.name for f in files] == ["summary.json", *(f"{s}.csv" for s in CSV)]
    files = io.write_results(result, tmp_path / "v",
                             options=io.OutputOptions(steps="last", figures=False, csv=False))
    assert [f.name for f in files] == ["summary.json", *(f"{s}.vtu" for s in SERIES)]
    assert not (tmp_path / "v" / "steps").exists()


def test_a_failed_write_of_an_assembly_leaves_nothing(result, tmp_path, monkeypatch):
    calls = []

    def second_fails(path, frame):
        calls.append(path.name)
        if len(calls) == 2:
            raise OSError(28, "No space left on device")

    monkeypatch.setattr(io, "_write_frame_csv", second_fails)
    with pytest.raises(OSError, match="No space left"):
        io.write_results(result, tmp_path / "out", options=io.OutputOptions(figures=False))
    assert calls == ["bottom+middle_frame.csv", "middle+top_frame.csv"]
    assert list(tmp_path.iterdir()) == []


def test_two_pairs_of_the_same_bodies_are_named_by_their_surfaces(result, tmp_path):
    """A body pair twice: both stems name the surfaces (characters a file
    name should not hold written as _); surfaces that still do not tell
    them apart: the pair's number."""
    p0, p1 = result.pairs
    twice = dataclasses.replace(result, pairs=[p0, dataclasses.replace(
        p1, names=("bottom", "middle"), surfaces=("xmax", "top face"))])
    files = io.write_results(twice, tmp_path / "o",
                             options=io.OutputOptions(steps="last", figures=False, vtu=False))
    assert [f.name for f in files][1:4] == [
        "bottom.zmax+middle.zmin_bottom_interface.csv",
        "bottom.zmax+middle.zmin_middle_interface.csv", "bottom.zmax+middle.zmin_frame.csv"]
    assert files[4].name == "bottom.xmax+middle.top_face_bottom_interface.csv"
    s = json.loads((tmp_path / "o" / "summary.json").read_text())
    assert [p["files"] for p in s["pairs"]] == ["bottom.zmax+middle.zmin",
                                                "bottom.xmax+middle.top_face"]
    assert pair_stems([(("a", "b"), ("top face", "s")), (("A", "B"), ("top/face", "s")),
                       (("a", "c"), ("x", "y"))]) == ["a+b.1", "A+B.2", "a+c"]
    # the same two bodies in the other order: still named by their surfaces
    assert pair_stems([(("a", "b"), ("s", "t")), (("b", "a"), ("u", "v"))]) == [
        "a.s+b.t", "b.u+a.v"]


@pytest.mark.parametrize("names, pairs, message", [
    (["a", "A", "c"], [(("a", "c"), ("s", "s")), (("A", "c"), ("t", "t"))],
     r"clashing file names \(A, a, compared ignoring case\)"),
    (["a+b", "a", "b"], [(("a", "b"), ("s", "s")), (("a+b", "b"), ("t", "t"))],
     r"body name 'a\+b' cannot name a file"),
    (["frame", "lower"], [], "clashing file names"),
    (["lower", "Lower_interface"], [], r"clashing file names \(Lower_interface, "
     r"lower_interface"),
    (["a", "b"], [(("a", "b"), ("s" * 240, "t")), (("a", "b"), ("u", "v"))],
     r"write_results: the file name 'a\.s{240}\+b\.t_a_interface_001\.vtu' is longer than "
     r"255 bytes"),
])
def test_names_that_would_clash_are_refused(names, pairs, message):
    with pytest.raises(bc.ConfigError, match=message):
        layout(names, pairs)


def test_body_names_of_an_assembly_that_are_safe():
    """No pair file can be a body's (body names hold no '+'): a body named
    'frame' or like another's two-body interface file is fine."""
    lay = layout(["frame", "a", "a_interface"], [(("frame", "a"), ("s", "s")),
                                                 (("a", "a_interface"), ("t", "t"))])
    assert lay.series() == [
        "frame", "a", "a_interface", "frame+a_frame_interface", "frame+a_a_interface",
        "frame+a_frame", "a+a_interface_a_interface", "a+a_interface_a_interface_interface",
        "a+a_interface_frame"]


def test_too_long_file_names_are_refused_before_writing(result, tmp_path):
    long = "b" * 130
    renamed = dataclasses.replace(
        result, names=("bottom", long, "top"),
        pairs=[dataclasses.replace(result.pairs[0], names=("bottom", long)),
               dataclasses.replace(result.pairs[1], names=(long, "top"))])
    with pytest.raises(bc.ConfigError, match=r"is longer than 255 bytes; use shorter body"):
        io.write_results(renamed, tmp_path / "out", options=io.OutputOptions(figures=False))
    assert list(tmp_path.iterdir()) == []


def test_a_two_body_run_keeps_its_plain_file_names(tmp_path):
    """The listing of a two-body run, steps/ and manifest included: each
    body's and the frame's own name, no pair prefix; no pairs in the
    summary."""
    lower = ElasticBody(box((0, 0, 0), (1, 1, 1), 2), LinearElastic(1e4, 0.3),
                        {"zmin": bc.Fixed()}, name="lower")
    upper = ElasticBody(box((0, 0, 1), (1, 1, 2), 1), LinearElastic(1e4, 0.3),
                        {"zmax": Displacement((0, 0, -0.01))}, name="upper")
    r = ContactProblem(lower, upper, ContactPair("zmax", "zmin")).solve(
        bc.SolverOptions(threads=1))
    out = tmp_path / "out"
    io.write_results(r, out, options=io.OutputOptions(figures=False))
    assert sorted(p.relative_to(out).as_posix() for p in out.rglob("*")) == [
        ".bemcontact-run.json", "frame.csv", "frame.pvd", "frame.vtu", "lower.pvd", "lower.vtu",
        "lower_interface.csv", "lower_interface.pvd", "lower_interface.vtu", "steps",
        "steps/frame_001.vtu", "steps/lower_001.vtu", "steps/lower_interface_001.vtu",
        "steps/upper_001.vtu", "steps/upper_interface_001.vtu", "summary.json", "upper.pvd",
        "upper.vtu", "upper_interface.csv", "upper_interface.pvd", "upper_interface.vtu",
    ]
    s = json.loads((out / "summary.json").read_text())
    assert "pairs" not in s and s["names"] == ["lower", "upper"]
