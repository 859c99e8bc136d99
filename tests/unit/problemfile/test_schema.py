"""The problem-file schema: one source for the reader's keys, ranges and
defaults and for the generated reference page; the mesh generators, the
output table and the pair's penalty override read from problem files."""

from __future__ import annotations

import dataclasses
import pathlib

import numpy as np
import pytest

import bemcontact as bc
from bemcontact.mesh import shapes as geometry
from bemcontact.problemfile import schema
from bemcontact.output.write import OutputOptions
from bemcontact.problemfile import load_problem

from .test_reader import BASE, edit, write

DOCS = pathlib.Path(__file__).resolve().parents[3] / "docs"


def test_reference_page_is_generated_from_the_schema():
    """docs/problem-file-reference.md is exactly what the schema generates
    (regenerate it with the command in its header comment)."""
    page = (DOCS / "problem-file-reference.md").read_text()
    assert page == schema.reference_markdown()


def _all_keys(key, out):
    out.append(key)
    for k in key.keys:
        _all_keys(k, out)
    if key.entry is not None:
        _all_keys(key.entry, out)
    return out


def test_every_key_is_documented_and_every_table_has_a_section():
    page = schema.reference_markdown()
    for k in _all_keys(schema.ROOT, []):
        if k is schema.ROOT:
            continue
        assert k.doc.strip(), k.name
        # named entries (<region>, <body>) are documented inside their parent's text
        assert f"`{k.name}`" in page or (k.name.startswith("<") and k.name in page), k.name
        if k.type in ("table", "tables") and k.keys:
            assert k.section, k.name


def test_solver_keys_ranges_and_defaults_are_solver_options_own():
    fields = {f.name: f for f in dataclasses.fields(bc.SolverOptions) if f.name != "progress"}
    assert schema.SOLVER.allowed == tuple(fields)
    for k in schema.SOLVER.keys:
        if k.name == "linear":
            continue
        if k.default is not schema.NO_DEFAULT:
            assert k.default == fields[k.name].default, k.name
        # the schema's bounds are the class's: just outside raises, just inside does not
        for bound, open_, side in ((k.lo, k.lo_open, -1), (k.hi, k.hi_open, +1)):
            if bound is None:
                continue
            inside = bound if not open_ else bound - side * (1 if k.type == "integer" else 1e-9)
            outside = bound + side * (1 if k.type == "integer" else 1e-9) if not open_ else bound
            if k.type == "integer":
                inside, outside = int(inside), int(outside)
            bc.SolverOptions(**{k.name: inside})
            with pytest.raises(bc.ConfigError):
                bc.SolverOptions(**{k.name: outside})


def test_linear_defaults_are_the_condensation_s_own():
    lin = bc.SolverOptions().linear  # the condensation's defaults
    h = lin.hmatrix
    for k in schema.LINEAR.keys:
        owner = h if k.name in schema.HMATRIX_KEYS else lin
        assert getattr(owner, k.name) == k.default, k.name


def test_solver_linear_table(tmp_path):
    text = edit(BASE, "max_iterations = 30",
                'max_iterations = 30\nlinear = { method = "hmatrix", eps = 1e-8, leaf_size = 16 }')
    p = load_problem(write(tmp_path, text), check_overlap=False)
    assert p.options.linear.method == "hmatrix"
    assert p.options.linear.hmatrix.eps == 1e-8 and p.options.linear.hmatrix.leaf_size == 16
    bad = edit(BASE, "max_iterations = 30", 'max_iterations = 30\nlinear = { methd = "dense" }')
    path = write(tmp_path, bad)
    with pytest.raises(bc.ConfigError, match=r"solver\.linear\.methd: unknown key.*'method'"):
        load_problem(path, check_overlap=False)


def test_output_defaults_are_output_options_own():
    fields = {f.name: f.default for f in dataclasses.fields(OutputOptions)}
    assert {k.name: k.default for k in schema.OUTPUT.keys} == fields


def test_output_table_and_penalty_override(tmp_path):
    text = BASE + '\npenalty = 3.5\n\n[output]\nsteps = "last"\nfigures = false\n'
    p = load_problem(write(tmp_path, text), check_overlap=False)
    assert p.output == OutputOptions(steps="last", figures=False)
    assert p.pair.penalty == 3.5 and p.options.penalty == 1.0  # the pair's, not the solver's
    assert load_problem(write(tmp_path, BASE), check_overlap=False).output == OutputOptions()


@pytest.mark.parametrize(
    "addition, field, message",
    [
        ('\n[output]\nstep = "all"\n', "output.step", "did you mean 'steps'?"),
        ('\n[output]\nsteps = "every"\n', "output.steps", "must be one of all, last"),
        ("\n[output]\nvtu = 1\n", "output.vtu", "must be true or false"),
        ("\npenalty = 0\n", "contact.penalty", "must be in [0.01, 100]"),
        ("\npenalty = 1e100\n", "contact.penalty", "must be in [0.01, 100]"),
    ],
)
def test_bad_output_and_penalty(tmp_path, addition, field, message):
    path = write(tmp_path, BASE + addition)
    with pytest.raises(bc.ConfigError) as info:
        load_problem(path, check_overlap=False)
    assert str(info.value).startswith(f"{path}: {field}: ")
    assert message in str(info.value)


CAP = (
    "cap = { radius = 5, height = 5, fine_size = 0.5, coarse_size = 2.5, fine_radius = 1, "
    "apex = [0, 0, 2], order = 1 }"
)


def test_cap_mesh_from_a_problem_file_is_the_geometry_function_s(tmp_path):
    """A generated cap is the mesh geometry.spherical_cap makes with the same
    arguments (defaults filled in from the schema)."""
    text = edit(
        BASE,
        'mesh = { box = { lower = [0, 0, 2], upper = [2, 2, 4], divisions = 1, '
        'element_type = "quad4" } }',
        f"mesh = {{ {CAP} }}",
    )
    text = edit(text, "[body.boundary_conditions.zmax]", "[body.boundary_conditions.base]")
    text = edit(text, 'surfaces = ["zmax", "zmin"]', 'surfaces = ["zmax", "contact"]')
    p = load_problem(write(tmp_path, text), check_overlap=False)
    direct = geometry.spherical_cap(5.0, 5.0, fine_size=0.5, coarse_size=2.5, fine_radius=1.0,
                                    apex=(0, 0, 2), order=1)
    mesh = p.bodies[1].mesh
    assert mesh.region_names == direct.region_names
    np.testing.assert_array_equal(mesh.elements, direct.elements)
    np.testing.assert_allclose(mesh.nodes, direct.nodes, rtol=0, atol=1e-12)


@pytest.mark.parametrize(
    "mesh, field, message",
    [
        (CAP.replace("height = 5", "height = 10"), "body[1].mesh.cap.height",
         "must be below 2 * radius = 10"),
        (CAP.replace("coarse_size = 2.5", "coarse_size = 0.1"), "body[1].mesh.cap.coarse_size",
         "must be >= fine_size = 0.5"),
        (CAP.replace("order = 1", "order = 3"), "body[1].mesh.cap.order", "must be in [1, 2]"),
        (CAP.replace("order = 1", "axis = 0"), "body[1].mesh.cap.axis", "must be one of 1, -1"),
        (CAP.replace("fine_radius", "fine_radus"), "body[1].mesh.cap.fine_radus",
         "did you mean 'fine_radius'?"),
        ("punch = { radius = 1, height = 1, fine_size = 0.1 }", "body[1].mesh.punch.coarse_size",
         "missing required key"),
        ("graded_box = { lower = [0, 0, 2], upper = [2, 2, 4], focus = [1, 1, 3], "
         "fine_size = 0.5, coarse_size = 1, fine_radius = 0.5 }", "body[1].mesh.graded_box",
         "must lie on a face of the box"),
        ('file = "x.msh", box = { lower = [0, 0, 0], upper = [1, 1, 1], divisions = 1 }',
         "body[1].mesh", "give exactly one of box, file, cap, punch, graded_box, ball (given: box, file)"),
        ('punch = { radius = 1, height = 1, fine_size = 0.1, coarse_size = 1 }, '
         'element_type = "tri6"', "body[1].mesh.element_type", "applies only to mesh files"),
    ],
)
def test_bad_generated_meshes(tmp_path, mesh, field, message):
    text = edit(
        BASE,
        'mesh = { box = { lower = [0, 0, 2], upper = [2, 2, 4], divisions = 1, '
        'element_type = "quad4" } }',
        f"mesh = {{ {mesh} }}",
    )
    path = write(tmp_path, text)
    with pytest.raises(bc.ConfigError) as info:
        load_problem(path, check_overlap=False)
    msg = str(info.value)
    assert "\n" not in msg
    assert msg.startswith(f"{path}: {field}: "), msg
    assert message in msg, msg
