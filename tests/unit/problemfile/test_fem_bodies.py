"""Finite-element bodies in a problem file (``model = "fem"``): the body a
file describes is the one the Python API builds (same result to round-off),
a run writes its volume file, a gmsh solid in bonded layers gets one
material per layer, and every bad input is one line naming the field, exit
2 and nothing written."""

from __future__ import annotations

import re

import numpy as np
import pytest

import bemcontact as bc
from bemcontact.cli import main
from bemcontact.problemfile import load_problem

from .test_reader import BASE, edit, write

pytest.importorskip("skfem")
pytest.importorskip("cvxopt")

from bemcontact.fem import BodyForce, FiniteElementBody, box_volume  # noqa: E402

FEM = edit(edit(BASE, 'name = "lower"\n', 'name = "lower"\nmodel = "fem"\n'),
           "upper = [2, 2, 2], divisions = 1 }", "upper = [2, 2, 2], divisions = 3, "
           'element_type = "hex27" }')


def test_a_fem_body_from_the_file_is_the_api_body(tmp_path):
    p = load_problem(write(tmp_path, FEM))
    lower, upper = p.bodies
    assert isinstance(lower, FiniteElementBody) and lower.volume.order == 2
    res = p.solve()
    api = FiniteElementBody(box_volume((0, 0, 0), (2, 2, 2), 3, "hex8", 2),
                            bc.LinearElastic(1e4, 0.3),
                            {"zmin": bc.Displacement((0, 0, 0))}, name="lower")
    ref = bc.ContactProblem(api, upper, p.pair).solve(p.options)
    assert res.converged and res.normal_force == pytest.approx(ref.normal_force, rel=1e-12)
    assert "finite-element body" in p.method_note


def test_a_run_writes_the_volume_file(tmp_path, capsys):
    out = tmp_path / "out"
    assert main(["run", str(write(tmp_path, FEM)), "--out", str(out), "--quiet"]) == 0
    assert (out / "lower_volume.vtu").is_file() and not (out / "upper_volume.vtu").exists()


def test_the_stress_output_of_a_fem_body_is_its_own_stresses(tmp_path):
    """``[[output.stresses]]`` on the finite-element body: the file's
    stresses are the body's (its elements' strains at the points), to the
    CSV's 17 digits."""
    line = ('\n[[output.stresses]]\nbody = "lower"\nline = { from = [1, 1, 1.9], '
            'to = [1, 1, 0.5], points = 8 }\n')
    path = write(tmp_path, FEM + line)
    out = tmp_path / "out"
    assert main(["run", str(path), "--out", str(out), "--quiet"]) == 0
    table = np.loadtxt(out / "stresses_lower_1.csv", delimiter=",", skiprows=1)
    res = load_problem(path).solve()
    want = res.stresses("lower", table[:, :3])
    voigt = table[:, [3, 4, 5, 7, 8, 6]]  # the file's sxx syy szz sxy syz sxz
    assert np.abs(voigt - want).max() <= 1e-12 * np.abs(want).max()
    assert np.abs(want[:, 2]).min() > 100  # the contact's compression: a real load


def test_a_layered_solid_has_a_material_per_layer(tmp_path):
    pytest.importorskip("gmsh")
    text = edit(FEM, "mesh = { box = { lower = [0, 0, 0], upper = [2, 2, 2], divisions = 3, "
                'element_type = "hex27" } }\nmaterial = { youngs_modulus = 1e4, poisson_ratio = 0.3 }',
                "mesh = { graded_box = { lower = [0, 0, 0], upper = [2, 2, 2], focus = [1, 1, 2], "
                "fine_size = 0.5, coarse_size = 1.0, fine_radius = 0.5, layers = [0.4] } }\n"
                "[body.materials.layer1]\nyoungs_modulus = 3e4\npoisson_ratio = 0.2\n"
                "[body.materials.substrate]\nyoungs_moduli = [1e4, 2e4, 3e4]\n"
                "poisson_ratios = [0.3, 0.2, 0.1]\nshear_moduli = [5e3, 6e3, 7e3]\n"
                "axis1 = [0, 1, 0]\naxis2 = [1, 0, 0]\n")
    lower = load_problem(write(tmp_path, text), check_overlap=False).bodies[0]
    v = lower.volume
    assert v.volume_names == ("layer1", "substrate")
    z = v.skfem.p[2, v.skfem.t].mean(axis=0)
    assert (z[v.cell_region == 0] > 1.6).all() and (z[v.cell_region == 1] < 1.6).all()
    assert lower.materials["layer1"] == bc.LinearElastic(3e4, 0.2)
    assert np.allclose(lower.materials["substrate"].rotation()[:, 2], [0, 0, -1])


GRAVITY = edit(FEM, LOWER_MAT := "material = { youngs_modulus = 1e4, poisson_ratio = 0.3 }",
               "material = { youngs_modulus = 1e4, poisson_ratio = 0.3, density = 1.0 }\n"
               "body_force = { gravity = [0, 0, -10] }")


def test_a_body_force_from_the_file_is_the_api_one(tmp_path):
    """The lower block's own weight (ρ g = 10 over its height of 2, a fifth
    of the contact's pressure) compresses it under the contact: the force
    differs from the weightless one by percents, and is the API body's to
    round-off."""
    p = load_problem(write(tmp_path, GRAVITY))
    lower, upper = p.bodies
    assert lower.body_force.gravity == (0.0, 0.0, -10.0) and lower.density == {"body": 1.0}
    res = p.solve()
    api = FiniteElementBody(box_volume((0, 0, 0), (2, 2, 2), 3, "hex8", 2),
                            bc.LinearElastic(1e4, 0.3), {"zmin": bc.Displacement((0, 0, 0))},
                            name="lower", density=1.0,
                            body_force=BodyForce(gravity=(0.0, 0.0, -10.0)))
    ref = bc.ContactProblem(api, upper, p.pair).solve(p.options)
    weightless = load_problem(write(tmp_path, FEM)).solve()
    assert res.converged and res.normal_force == pytest.approx(ref.normal_force, rel=1e-12)
    assert not res.normal_force == pytest.approx(weightless.normal_force, rel=1e-2)
    # the support carries the contact force and the weight 10 x 8
    assert res.bodies[0].reaction("zmin")[2] == pytest.approx(res.normal_force + 80, rel=1e-9)


STIFF = "[[1, 0, 0, 0, 0, 0], [0, 1, 0, 0, 0, 0], [0, 0, 1, 0, 0, 0], [0, 0, 0, 1, 0, 0], " \
        "[0, 0, 0, 0, -1, 0], [0, 0, 0, 0, 0, 1]]"


@pytest.mark.parametrize("old, new, field, what", [
    (LOWER_MAT, f"material = {{ stiffness = {STIFF} }}", "body[0].material",
     "stiffness is not positive definite"),
    (LOWER_MAT, "[body.materials.substrate]\nyoungs_modulus = 1e4\npoisson_ratio = 0.3\n",
     "body[0].materials.substrate", "no volume region 'substrate'"),
    ('element_type = "hex27"', 'element_type = "quad8"', "body[0].mesh.box.element_type",
     "is a surface element"),
    ("divisions = 3, ", "divisions = 3, grading = 2, ", "body[0].mesh.box.grading",
     "a finite-element box is uniform"),
    ('model = "fem"\n', 'model = "fe"\n', "body[0].model", "must be one of bem, fem"),
    (LOWER_MAT, "material = { youngs_moduli = [1e4, 1e4, 1e4], poisson_ratio = 0.3 }",
     "body[0].material", "not both isotropic and orthotropic"),
    ('frame = "mortar"', 'frame = "mortar"\nmethod = "multiscale"', "contact.method",
     "the contact grid takes BEM bodies"),
    (LOWER_MAT, LOWER_MAT + "\nbody_force = { gravity = [0, 0, -1] }",
     "body[0].material.density", "missing: the body force needs the density"),
    (LOWER_MAT, LOWER_MAT + "\nbody_force = { gravty = [0, 0, -1] }",
     "body[0].body_force.gravty", "unknown key"),
    (LOWER_MAT, LOWER_MAT + "\nbody_force = { gravity = [0, -1] }",
     "body[0].body_force.gravity", "3"),
    ("poisson_ratio = 0.3 }", "poisson_ratio = 0.3, density = -1 }",
     "body[0].material.density", ">= 0"),
])
def test_bad_fem_input_is_one_line_exit_2_nothing_written(tmp_path, capsys, old, new, field,
                                                           what):
    path = write(tmp_path, edit(FEM, old, new))
    out = tmp_path / "out"
    assert main(["run", str(path), "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and f"{path}: {field}" in err and what in err, err
    assert not out.exists()


@pytest.mark.parametrize("old, new, field, what", [
    ('element_type = "quad4"', 'element_type = "tet10"', "body[1].mesh.box.element_type",
     "is a volume element"),
    ("material = { youngs_modulus = 2e4, poisson_ratio = 0.25 }",
     "material = { youngs_moduli = [1e4, 1e4, 1e4], poisson_ratios = [0.3, 0.3, 0.3], "
     "shear_moduli = [4e3, 4e3, 4e3] }", "body[1].material.youngs_moduli",
     "needs a finite-element body"),
    ("material = { youngs_modulus = 2e4, poisson_ratio = 0.25 }",
     "material = { youngs_modulus = 2e4, poisson_ratio = 0.25, density = 1 }\n"
     "body_force = { gravity = [0, 0, -1] }", "body[1].body_force",
     "needs a finite-element body"),
])
def test_fem_only_keys_on_a_bem_body_are_refused(tmp_path, old, new, field, what):
    with pytest.raises(bc.ConfigError, match=re.escape(f"{field}: {what}")):
        load_problem(write(tmp_path, edit(FEM, old, new)))


def test_a_surface_mesh_file_for_a_fem_body_is_one_line(tmp_path, capsys):
    pytest.importorskip("meshio").write(tmp_path / "skin.vtu", bc.box((0, 0, 0), (2, 2, 2), 2).to_meshio())
    text = edit(FEM, "mesh = { box = { lower = [0, 0, 0], upper = [2, 2, 2], divisions = 3, "
                'element_type = "hex27" } }', 'mesh = { file = "skin.vtu" }')
    path = write(tmp_path, text)
    assert main(["check", str(path)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1, err
    assert f"{path}: body[0].mesh.file: cannot use the mesh file" in err
    assert "a volume mesh, not a surface mesh" in err
