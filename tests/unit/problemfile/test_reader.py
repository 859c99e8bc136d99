"""Problem files: valid files load into the right objects; every kind of bad
input is a ConfigError with a one-line message naming the file, the dotted
field path and the offending value."""

from __future__ import annotations

import sys
import warnings

import numpy as np
import pytest

import bemcontact as bc
from bemcontact.output.write import OutputOptions
from bemcontact.problemfile import load_problem

# Two small cubes (1 and 1 divisions): cheap to mesh and to build the frame of.
BASE = """\
title = "tiny cubes"
units = { length = "mm", force = "N", stress = "MPa" }

[solver]
tolerance = 1e-10
max_iterations = 30

[[body]]
name = "lower"
mesh = { box = { lower = [0, 0, 0], upper = [2, 2, 2], divisions = 1 } }
material = { youngs_modulus = 1e4, poisson_ratio = 0.3 }

[body.boundary_conditions.zmin]
displacement = [0, 0, 0]

[[body]]
name = "upper"
mesh = { box = { lower = [0, 0, 2], upper = [2, 2, 4], divisions = 1, element_type = "quad4" } }
material = { youngs_modulus = 2e4, poisson_ratio = 0.25 }

[body.boundary_conditions.zmax]
displacement = [0, 0, -0.04]

[contact]
bodies = ["lower", "upper"]
surfaces = ["zmax", "zmin"]
friction_coefficient = 0.1
frame = "mortar"
"""


def write(tmp_path, text, name="problem.toml"):
    p = tmp_path / name
    p.write_text(text)
    return p


def edit(text, old, new):
    assert old in text, old
    return text.replace(old, new, 1)


# ----------------------------------------------------------------------------- valid files


def test_base_file_loads_into_the_api_objects(tmp_path):
    p = load_problem(write(tmp_path, BASE))
    assert isinstance(p, bc.Problem)
    assert p.title == "tiny cubes" and p.units["force"] == "N"
    lower, upper = p.bodies
    assert (lower.name, upper.name) == ("lower", "upper")
    assert lower.material == bc.LinearElastic(1e4, 0.3)
    assert upper.material == bc.LinearElastic(2e4, 0.25)
    assert lower.mesh.n_elements == 6 and upper.mesh.element_type == "quad4"
    assert np.allclose(upper.mesh.nodes.min(axis=0), [0, 0, 2])
    (bcz,) = lower.boundary_conditions["zmin"]
    assert bcz == bc.Displacement((0.0, 0.0, 0.0))
    assert p.pair == bc.ContactPair("zmax", "zmin", friction_coefficient=0.1, frame="mortar",
                                   bodies=("lower", "upper"))
    assert p.options == bc.SolverOptions(tolerance=1e-10, max_iterations=30)
    assert p.echo["file"] == str(tmp_path / "problem.toml")
    assert p.echo["body"][1]["material"]["youngs_modulus"] == 2e4
    cp = p.contact_problem()
    assert isinstance(cp, bc.ContactProblem) and cp is p.contact_problem()
    assert cp.bodies == p.bodies and cp.pair is p.pair


def test_defaults_and_optional_sections(tmp_path):
    text = BASE.split("[solver]")[0] + BASE.split("max_iterations = 30\n")[1]
    text = edit(text, 'title = "tiny cubes"\n', "")
    text = edit(text, 'units = { length = "mm", force = "N", stress = "MPa" }\n', "")
    text = edit(text, 'bodies = ["lower", "upper"]\n', "")
    text = edit(text, "friction_coefficient = 0.1\n", "")
    text = edit(text, 'frame = "mortar"\n', "")
    p = load_problem(write(tmp_path, text))
    assert p.title == "" and dict(p.units) == {}
    assert p.options == bc.SolverOptions()
    assert p.pair == bc.ContactPair("zmax", "zmin", 0.0, "mortar", bodies=("lower", "upper"))
    assert [b.name for b in p.bodies] == ["lower", "upper"]


def test_figures_default_on_only_with_matplotlib(tmp_path, monkeypatch):
    """No `figures` key: figures with matplotlib; without it they are off
    and an OptionalDependencyWarning names the install command, once the
    whole file has been read (no warning before an error)."""
    src = write(tmp_path, BASE)
    assert load_problem(src).output.figures is True
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    with pytest.warns(bc.OptionalDependencyWarning,
                      match=r'^figures skipped .*pip install "bemcontact\[plot\]"') as w:
        p = load_problem(src)
    assert len(w) == 1 and w[0].filename == __file__  # points at the caller
    assert p.output == OutputOptions(figures=False)
    bad = write(tmp_path, edit(BASE, "friction_coefficient = 0.1", "friction_coefficient = -1"))
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # a warning would raise instead of the ConfigError
        with pytest.raises(bc.ConfigError, match="contact.friction_coefficient"):
            load_problem(bad)


def test_figures_asked_for_without_matplotlib_are_refused(tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    src = write(tmp_path, BASE + "\n[output]\nfigures = true\n")
    with pytest.raises(bc.ConfigError, match=r'output.figures: needs matplotlib.*"bemcontact\[plot'):
        load_problem(src)
    off = write(tmp_path, BASE + "\n[output]\nfigures = false\n", "off.toml")
    assert load_problem(off).output.figures is False  # and no warning (filterwarnings = error)


def test_contact_bodies_order_sets_body_1(tmp_path):
    text = edit(BASE, 'bodies = ["lower", "upper"]', 'bodies = ["upper", "lower"]')
    text = edit(text, 'surfaces = ["zmax", "zmin"]', 'surfaces = ["zmin", "zmax"]')
    p = load_problem(write(tmp_path, text))
    assert [b.name for b in p.bodies] == ["upper", "lower"]
    assert (p.pair.surface1, p.pair.surface2) == ("zmin", "zmax")


def test_free_components_traction_pressure_and_all_solver_keys(tmp_path):
    text = edit(
        BASE,
        "[body.boundary_conditions.zmax]\ndisplacement = [0, 0, -0.04]",
        '[body.boundary_conditions.zmax]\ndisplacement = ["free", 0, -0.04]\n'
        "traction = [0.5, \"free\", \"free\"]\n"
        "[body.boundary_conditions.xmin]\npressure = 2",
    )
    text = edit(
        text, "max_iterations = 30",
        "max_iterations = 30\nload_steps = 2\npenalty = 2\nline_search_sigma = 1e-3\n"
        "min_step = 1e-8\nthreads = 1\nwatchdog = 0",
    )
    p = load_problem(write(tmp_path, text), check_overlap=False)
    upper = p.bodies[1]
    assert upper.boundary_conditions["zmax"] == (
        bc.Displacement((None, 0.0, -0.04)), bc.Traction((0.5, None, None)),
    )
    assert upper.boundary_conditions["xmin"] == (bc.Pressure(2.0),)
    assert p.options == bc.SolverOptions(
        tolerance=1e-10, max_iterations=30, load_steps=2, penalty=2.0, line_search_sigma=1e-3,
        min_step=1e-8, threads=1, watchdog=0,
    )
    assert isinstance(p.options.penalty, float)


def test_mesh_file_relative_to_the_problem_file(tmp_path):
    (tmp_path / "meshes").mkdir()
    bc.box((0, 0, 0), (2, 2, 2), 2, "tri3").to_meshio().write(tmp_path / "meshes" / "lower.vtu")
    text = edit(
        BASE, "mesh = { box = { lower = [0, 0, 0], upper = [2, 2, 2], divisions = 1 } }",
        'mesh = { file = "meshes/lower.vtu" }',
    )
    # a file written by bemcontact has regions region0..region5 (xmin..zmax)
    text = edit(text, "[body.boundary_conditions.zmin]", "[body.boundary_conditions.region4]")
    text = edit(text, 'surfaces = ["zmax", "zmin"]', 'surfaces = ["region5", "zmin"]')
    sub = tmp_path / "problems"
    sub.mkdir()
    text = text.replace('file = "meshes/', 'file = "../meshes/')
    p = load_problem(write(sub, text))
    assert p.bodies[0].mesh.element_type == "tri3"
    assert p.bodies[0].mesh.n_elements == 48


def test_force_steps_and_search_distance(tmp_path):
    """force = [...] becomes a Force condition, [[step]] sections LoadSteps in
    order (changes only, with labels and increments), search_distance the
    pair's."""
    text = edit(BASE, "displacement = [0, 0, -0.04]",
                'displacement = ["free", 0, "free"]\nforce = [0, "free", -10]')
    text = edit(text, 'frame = "mortar"\n', 'frame = "mortar"\nsearch_distance = 0.5\n'
                'frame_on = "upper"\n[[step]]\nlabel = "P"\n'
                '[[step]]\nlabel = "Q"\nincrements = 4\n'
                '[step.boundary_conditions.upper.zmax]\n'
                'displacement = ["free", 0, "free"]\nforce = [2, "free", -10]\n')
    p = load_problem(write(tmp_path, text))
    upper = p.bodies[1]
    assert upper.boundary_conditions["zmax"] == (
        bc.Displacement((None, 0.0, None)), bc.Force((0.0, None, -10.0)))
    assert p.pair.search_distance == 0.5
    assert p.pair.frame_on == "body2"
    assert p.contact_problem().frame.owner == 1
    assert [(s.label, s.increments) for s in p.steps] == [("P", 1), ("Q", 4)]
    assert p.steps[0].conditions == {}
    assert p.steps[1].conditions["upper"]["zmax"][1] == bc.Force((2.0, None, -10.0))


# ----------------------------------------------------------------------------- bad input


def expect_error(tmp_path, text, field, value, *also):
    path = write(tmp_path, text)
    with pytest.raises(bc.ConfigError) as info:
        load_problem(path)
    msg = str(info.value)
    assert "\n" not in msg, msg
    assert msg.startswith(f"{path}: {field}: "), msg
    assert f"got {value}" in msg, msg
    for s in also:
        assert s in msg, msg
    return msg


BAD = {
    # case: (old, new, field, value repr, extra substrings)
    "unknown top-level key": (
        "[solver]", "[solvr]", "solvr", "'solvr'", "did you mean 'solver'?"),
    "unknown nested key": (
        "youngs_modulus = 1e4", "youngs_modulu = 1e4", "body[0].material.youngs_modulu",
        "'youngs_modulu'", "did you mean 'youngs_modulus'?"),
    "missing key": (
        "material = { youngs_modulus = 2e4, poisson_ratio = 0.25 }",
        "material = { youngs_modulus = 2e4 }", "body[1].material.poisson_ratio",
        "{'youngs_modulus': 20000.0}", "missing required key"),
    "boolean is not a number": (
        "tolerance = 1e-10", "tolerance = true", "solver.tolerance", "True", "not a boolean"),
    "nan": ("tolerance = 1e-10", "tolerance = nan", "solver.tolerance", "nan", "finite"),
    "inf modulus": (
        "youngs_modulus = 1e4", "youngs_modulus = inf", "body[0].material.youngs_modulus",
        "inf", "finite"),
    "solver range": (
        "tolerance = 1e-10", "tolerance = 2", "solver.tolerance", "2", "must be in (0, 1)"),
    "float for an integer": (
        "max_iterations = 30", "max_iterations = 30.0", "solver.max_iterations", "30.0",
        "write 30"),
    "negative watchdog": ("max_iterations = 30", "watchdog = -1", "solver.watchdog", "-1", ">= 0"),
    "zero threads": ("max_iterations = 30", "threads = 0", "solver.threads", "0", "must be in [1, 4096]"),
    "E <= 0": (
        "youngs_modulus = 2e4", "youngs_modulus = 0", "body[1].material.youngs_modulus", "0",
        "must be > 0"),
    "nu = 0.5": (
        "poisson_ratio = 0.3", "poisson_ratio = 0.5", "body[0].material.poisson_ratio", "0.5",
        "must be in (-1, 0.5)"),
    "nu = -1": (
        "poisson_ratio = 0.3", "poisson_ratio = -1", "body[0].material.poisson_ratio", "-1",
        "must be in (-1, 0.5)"),
    "string modulus": (
        "youngs_modulus = 1e4", 'youngs_modulus = "1e4"', "body[0].material.youngs_modulus",
        "'1e4'", "not a string"),
    "negative friction": (
        "friction_coefficient = 0.1", "friction_coefficient = -0.1",
        "contact.friction_coefficient", "-0.1", ">= 0"),
    "frame rule": ('frame = "mortar"', 'frame = "mortr"', "contact.frame", "'mortr'",
                   "did you mean 'mortar'?"),
    "unknown body in contact": (
        'bodies = ["lower", "upper"]', 'bodies = ["lower", "uper"]', "contact.bodies[1]",
        "'uper'", "did you mean 'upper'?"),
    "same body twice in contact": (
        'bodies = ["lower", "upper"]', 'bodies = ["lower", "lower"]', "contact.bodies",
        "['lower', 'lower']"),
    "contact surface not in the mesh": (
        'surfaces = ["zmax", "zmin"]', 'surfaces = ["zmax", "bottom"]', "contact.surfaces[1]",
        "'bottom'", "its regions: xmin, xmax, ymin, ymax, zmin, zmax"),
    "boundary condition region not in the mesh": (
        "[body.boundary_conditions.zmin]", "[body.boundary_conditions.zmn]",
        "body[0].boundary_conditions.zmn", "'zmn'", "did you mean 'zmin'?", "its regions"),
    "boundary condition on the contact surface": (
        "[body.boundary_conditions.zmax]\ndisplacement = [0, 0, -0.04]",
        "[body.boundary_conditions.zmax]\ndisplacement = [0, 0, -0.04]\n"
        "[body.boundary_conditions.zmin]\ntraction = [0, 0, 1]",
        "body[1].boundary_conditions.zmin", "{'traction': [0, 0, 1]}", "contact.surfaces[1]",
        "remove this table"),
    "duplicate body names": (
        'name = "upper"', 'name = "lower"', "body[1].name", "'lower'", "duplicate"),
    "reserved body name": ('name = "upper"', 'name = "frame"', "body[1].name", "'frame'"),
    "body name too long for a file name": (
        'name = "upper"', f'name = "{"u" * 250}"', "body[1].name", "'uuuuuuuu",
        "longer than 64 characters"),
    "body names whose output files clash": (
        'name = "upper"', 'name = "lower_interface"', "body[1].name", "'lower_interface'",
        "clashes with the output files of body 'lower' (lower_interface.vtu)"),
    "body name not a file name": (
        'name = "upper"', 'name = "up/per"', "body[1].name", "'up/per'"),
    "free misspelled": (
        "displacement = [0, 0, -0.04]", 'displacement = ["fre", 0, -0.04]',
        "body[1].boundary_conditions.zmax.displacement[0]", "'fre'", "did you mean 'free'?"),
    "two components": (
        "displacement = [0, 0, -0.04]", "displacement = [0, -0.04]",
        "body[1].boundary_conditions.zmax.displacement", "[0, -0.04]", "3 values"),
    "component prescribed twice": (
        "displacement = [0, 0, -0.04]", 'displacement = [0, 0, -0.04]\ntraction = ["free", 1, 2]',
        "body[1].boundary_conditions.zmax.traction[1]", "1", "both displacement and traction"),
    "pressure with displacement": (
        "displacement = [0, 0, -0.04]", "displacement = [0, 0, -0.04]\npressure = 1",
        "body[1].boundary_conditions.zmax.displacement", "[0, 0, -0.04]", "pressure"),
    "empty condition": (
        "[body.boundary_conditions.zmax]\ndisplacement = [0, 0, -0.04]",
        "[body.boundary_conditions.zmax]\ndisplacement = [0, 0, -0.04]\n"
        "[body.boundary_conditions.xmax]", "body[1].boundary_conditions.xmax", "{}",
        "no condition"),
    "box upper below lower": (
        "upper = [2, 2, 4]", "upper = [2, 2, 1]", "body[1].mesh.box.upper[2]", "1",
        "must exceed lower[2] = 2"),
    "zero divisions": (
        "divisions = 1 } }\nmaterial = { youngs_modulus = 1e4",
        "divisions = 0 } }\nmaterial = { youngs_modulus = 1e4", "body[0].mesh.box.divisions",
        "0", ">= 1"),
    "element type": (
        'element_type = "quad4"', 'element_type = "quad"', "body[1].mesh.box.element_type",
        "'quad'", "did you mean"),
    "box and file": (
        "divisions = 1 } }\nmaterial = { youngs_modulus = 1e4",
        'divisions = 1 }, file = "x.msh" }\nmaterial = { youngs_modulus = 1e4',
        "body[0].mesh", "{'box':", "exactly one of box"),
    "missing mesh file": (
        "mesh = { box = { lower = [0, 0, 0], upper = [2, 2, 2], divisions = 1 } }",
        'mesh = { file = "nowhere.msh" }', "body[0].mesh.file", "'nowhere.msh'",
        "no such mesh file"),
    "force and displacement on one component": (
        "displacement = [0, 0, -0.04]", 'displacement = [0, 0, "free"]\nforce = [1, "free", -5]',
        "body[1].boundary_conditions.zmax.force[0]", "1", "both displacement and force"),
    "search distance not positive": (
        'frame = "mortar"', 'frame = "mortar"\nsearch_distance = 0', "contact.search_distance",
        "0", "must be > 0"),
    "frame on an unknown body": (
        'frame = "mortar"', 'frame = "mortar"\nframe_on = "uper"', "contact.frame_on",
        "'uper'", "did you mean 'upper'?"),
    "step with unknown key": (
        'frame = "mortar"\n', 'frame = "mortar"\n[[step]]\nincrement = 2\n', "step[0].increment",
        "'increment'", "did you mean 'increments'?"),
    "step with zero increments": (
        'frame = "mortar"\n', 'frame = "mortar"\n[[step]]\nincrements = 0\n',
        "step[0].increments", "0", ">= 1"),
    "step on an unknown body": (
        'frame = "mortar"\n',
        'frame = "mortar"\n[[step]]\n[step.boundary_conditions.uper.zmax]\npressure = 1\n',
        "step[0].boundary_conditions.uper", "'uper'", "did you mean 'upper'?"),
    "step changes the kind of a condition": (
        'frame = "mortar"\n',
        'frame = "mortar"\n[[step]]\nlabel = "push"\n'
        '[step.boundary_conditions.upper.zmax]\nforce = [0, 0, -10]\n',
        "step[0]", "'push'", "component x changes from displacement to force"),
    "non-overlapping contact surfaces": (
        "lower = [0, 0, 2], upper = [2, 2, 4]", "lower = [5, 0, 2], upper = [7, 2, 4]",
        "contact.surfaces", "['zmax', 'zmin']", "do not overlap"),
}


@pytest.mark.parametrize("case", list(BAD), ids=list(BAD))
def test_bad_input_names_file_field_and_value(tmp_path, case):
    old, new, field, value, *also = BAD[case]
    expect_error(tmp_path, edit(BASE, old, new), field, value, *also)


def test_one_body_only(tmp_path):
    first = BASE.split('[[body]]\nname = "upper"')[0]
    text = first + BASE.split("displacement = [0, 0, -0.04]\n")[1]
    expect_error(tmp_path, text, "body", "['lower']", "at least two")


def test_body_as_table_not_array(tmp_path):
    text = '[body]\nname = "a"\n[contact]\nsurfaces = ["a", "b"]\n'
    expect_error(tmp_path, text, "body", "{'name': 'a'}", "[[body]]")


def test_unreadable_mesh_file(tmp_path):
    (tmp_path / "lower.msh").write_text("this is not a mesh\n")
    text = edit(
        BASE, "mesh = { box = { lower = [0, 0, 0], upper = [2, 2, 2], divisions = 1 } }",
        'mesh = { file = "lower.msh" }',
    )
    expect_error(tmp_path, text, "body[0].mesh.file", "'lower.msh'", "cannot use the mesh file")


def test_open_mesh_file_is_reported_on_the_mesh(tmp_path):
    m = bc.box((0, 0, 0), (2, 2, 2), 1)
    keep = np.flatnonzero(m.element_region != m.region_names.index("xmin"))
    regions = {n: np.flatnonzero(m.element_region[keep] == i) for i, n in enumerate(m.region_names)
               if n != "xmin"}
    open_mesh = bc.SurfaceMesh(m.nodes, m.elements[keep], "quad4", regions)
    open_mesh.to_meshio().write(tmp_path / "open.vtu")
    text = edit(
        BASE, "mesh = { box = { lower = [0, 0, 0], upper = [2, 2, 2], divisions = 1 } }",
        'mesh = { file = "open.vtu" }',
    )
    text = edit(text, "[body.boundary_conditions.zmin]", "[body.boundary_conditions.region3]")
    text = edit(text, 'surfaces = ["zmax", "zmin"]', 'surfaces = ["region4", "zmin"]')
    expect_error(tmp_path, text, "body[0].mesh", "{'file': 'open.vtu'}", "not closed")


def test_invalid_toml_and_missing_file(tmp_path):
    path = write(tmp_path, BASE + "\nthis is = = wrong\n")
    with pytest.raises(bc.ConfigError, match=r"problem\.toml: not a valid TOML file: .*line 3\d"):
        load_problem(path)
    with pytest.raises(bc.ConfigError, match=r"nothere\.toml: cannot read the problem file"):
        load_problem(tmp_path / "nothere.toml")


def test_overlap_check_can_be_deferred(tmp_path):
    text = edit(
        BASE, "lower = [0, 0, 2], upper = [2, 2, 4]", "lower = [5, 0, 2], upper = [7, 2, 4]"
    )
    p = load_problem(write(tmp_path, text), check_overlap=False)
    with pytest.raises(bc.ConfigError, match="do not overlap"):
        p.contact_problem().frame


def test_solve_follows_the_file_s_load_steps_as_the_command_line_does(tmp_path):
    """ProblemFile.solve() applies the [[step]] history (a later tangential
    step here): the same forces as `bemcontact run`, to round-off, and a
    tangential force that the first step alone would not give."""
    import json

    from bemcontact.cli import main

    text = edit(BASE, 'frame = "mortar"\n', 'frame = "mortar"\n[[step]]\nlabel = "P"\n'
                '[[step]]\nlabel = "shift"\nincrements = 2\n'
                '[step.boundary_conditions.upper.zmax]\ndisplacement = [0.002, 0, -0.04]\n'
                '[output]\nfigures = false\nvtu = false\n')
    src = write(tmp_path, text)
    p = load_problem(src)
    res = p.solve()
    assert [h.label for h in res.history] == ["P", "shift"]
    first = p.contact_problem().solve(p.options)  # the first step only: no shift
    assert abs(first.tangential_force) < 1e-9 * first.normal_force
    assert res.tangential_force > 1e-3 * res.normal_force
    files = p.write(res, tmp_path / "api")
    assert {f.name for f in files} >= {"summary.json", "frame.csv"}
    assert main(["run", str(src), "--out", str(tmp_path / "cli"), "--quiet"]) == 0
    api = json.loads((tmp_path / "api" / "summary.json").read_text())
    cli = json.loads((tmp_path / "cli" / "summary.json").read_text())
    for key in ("normal_force", "tangential_force"):
        assert api[key] == pytest.approx(cli[key], rel=1e-12), key
