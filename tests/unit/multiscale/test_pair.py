"""A two-body problem solved on the contact grid (multiscale/pair.py) and
through the problem file (``[contact] method``): the contact plane and the
surfaces' shape found from coarse meshes, the force against the full path,
the files of ``bemcontact run``, the applicability checks that send a
contact near an edge or on a thin layer to the full path, and bad input."""

from __future__ import annotations

import json

import numpy as np
import pytest
import scipy.spatial

from bemcontact.bem import Displacement, ElasticBody, Fixed, LinearElastic
from bemcontact.cli import main
from bemcontact.contact import ContactPair, ContactProblem, SolverOptions
from bemcontact.errors import ConfigError
from bemcontact.mesh import shapes
from bemcontact.multiscale.pair import applicability, solve_on_grid
from bemcontact.problemfile.method import on_grid
from bemcontact.validation import cases

STEEL = LinearElastic(210000.0, 0.3)


def coarse_sphere_on_block(friction: float = 0.0):
    """The benchmark's bodies meshed at the scale of their geometry (0.5 mm
    near the contact, growing by 0.45 per mm to 2.5 mm: 778 + 403 nodes)."""
    return cases.sphere_on_block(0.5, 0.03, friction_coefficient=friction,
                                 setup=cases.SphereOnBlock(fine_radius=1.0, growth=0.45))


def test_the_contact_plane_and_the_shapes_come_from_the_coarse_meshes(full_sphere_on_block):
    """The apex found to 2e-4 mm (a fifth of the finest coarse element is
    0.1 mm; the quartic fits of the nodes locate it to measured 1.4e-4), the
    normal z, the sphere's curvature 1/R within 0.5 % (measured 0.07 %), the
    block's zero to 1e-12; the force (cells of a/25) within 0.5 % of the full
    path's at a/h = 8 (measured −0.27 %; that reference is itself about 0.15 %
    above the full path's converged force: docs/validation.md), the checks of
    the contact conditions met."""
    res = solve_on_grid(coarse_sphere_on_block())
    assert np.linalg.norm(res.origin) < 2e-4
    assert np.allclose(res.axes, np.eye(3))
    block, sphere = res.corrections
    assert np.allclose(sphere.curvature, 0.1, rtol=5e-3)
    assert np.abs(block.curvature).max() < 1e-12
    P_full = full_sphere_on_block[0]
    assert abs(res.history[-1].force[2] / P_full - 1.0) < 0.005
    s = res.summary()
    assert s["steps"][0]["rigid_displacement"] == pytest.approx([0.0, 0.0, -0.03])
    assert all(c["worst"] <= c["tolerance"] for c in s["steps"][0]["verification"].values())
    assert applicability(res, coarse_sphere_on_block())["reason"] == ""


HERTZ = """\
title = "Hertz on the contact grid"
units = {{ length = "mm", force = "N", stress = "MPa" }}

[[body]]
name = "block"
mesh = {{ graded_box = {{ lower = [-10, -10, -10], upper = [10, 10, 0], focus = [0, 0, 0], \
fine_size = 0.5, coarse_size = 2.5, fine_radius = 1.0 }} }}
material = {{ youngs_modulus = 210e3, poisson_ratio = 0.3 }}
[body.boundary_conditions.zmin]
displacement = [0, 0, 0]
{extra}
[[body]]
name = "sphere"
mesh = {{ cap = {{ radius = 10, height = 10, fine_size = 0.5, coarse_size = 2.5, \
fine_radius = 1.0 }} }}
material = {{ youngs_modulus = 210e3, poisson_ratio = 0.3 }}
[body.boundary_conditions.base]
displacement = [0, 0, -0.03]

[contact]
bodies = ["block", "sphere"]
surfaces = ["zmax", "contact"]
method = "{method}"
grid_size = 0.04
"""


def test_run_with_method_multiscale_writes_the_grid_files(tmp_path, capsys, full_sphere_on_block):
    """``bemcontact run`` on the Hertz example with ``method = "multiscale"``
    and coarse meshes: exit 0, the line that says the grid solved it, the
    grid's files (each body's too), and in summary.json the method with its applicability
    checks, the corrections' estimates and a normal force within 1 % of the
    full path's at a/h = 8."""
    path = tmp_path / "hertz.toml"
    path.write_text(HERTZ.format(method="multiscale", extra=""))
    out = tmp_path / "out"
    assert main(["run", str(path), "--out", str(out)]) == 0
    text = capsys.readouterr().out
    assert 'contact.method = "multiscale": the contact grid' in text
    names = {p.name for p in out.iterdir()}
    assert {"summary.json", "grid.csv", "grid.vtu", "block.vtu", "sphere.vtu"} <= names
    # each body's fields on its own mesh (tests/unit/multiscale/test_result.py):
    # the sphere's platen moved by its prescribed 0.03 mm, its apex less
    import meshio

    sphere = meshio.read(out / "sphere.vtu")
    uz = sphere.point_data["displacement"][:, 2]
    assert uz.min() == pytest.approx(-0.03, abs=1e-6) and -0.03 < uz.max() < -0.01
    s = json.loads((out / "summary.json").read_text())
    assert s["method"]["used"] == "multiscale" and s["method"]["requested"] == "multiscale"
    assert all(c["holds"] for c in s["method"]["applicability"].values())
    assert s["grid"]["cell_size"] == [0.04, 0.04]
    assert max(c["estimate"] for c in s["corrections"].values()) < 1e-2
    assert abs(s["steps"][0]["normal_force"] / full_sphere_on_block[0] - 1.0) < 0.01
    rows = np.loadtxt(out / "grid.csv", delimiter=",", skiprows=1)
    assert rows.shape == (s["grid"]["nx"] * s["grid"]["ny"], 12)
    # the cells' pressures carry the normal force
    assert rows[:, 3].sum() * 0.04**2 == pytest.approx(s["steps"][0]["normal_force"], rel=1e-9)


def test_a_load_the_grid_cannot_take_is_one_line_exit_2(tmp_path, capsys):
    """A pressure on a face: method = "multiscale" refuses it in one line
    naming the body, the region and the way out; nothing is written."""
    path = tmp_path / "hertz.toml"
    path.write_text(HERTZ.format(method="multiscale",
                                 extra="[body.boundary_conditions.xmin]\npressure = 1.0\n"))
    out = tmp_path / "out"
    assert main(["run", str(path), "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1
    assert "block" in err and "xmin" in err and 'method = "full"' in err
    assert not out.exists()


def _on_layer(thickness: float, offset: float = 0.0) -> ContactProblem:
    """The coarse sphere on a block of the given thickness, its apex
    ``offset`` from the block's centre toward its x = +10 edge."""
    blk = shapes.graded_block((-10.0, -10.0, -thickness), (10.0, 10.0, 0.0), (offset, 0.0, 0.0),
                              fine_size=min(0.5, thickness / 2), coarse_size=2.5, fine_radius=1.0,
                              growth=0.45)
    cap = shapes.spherical_cap(10.0, 10.0, apex=(offset, 0.0, 0.0), axis=1, fine_size=0.5,
                               coarse_size=2.5, fine_radius=1.0, growth=0.45)
    block = ElasticBody(blk, STEEL, {"zmin": Fixed()}, name="block")
    sphere = ElasticBody(cap, STEEL, {"base": Displacement((0.0, 0.0, -0.03))}, name="sphere")
    return ContactProblem(block, sphere, ContactPair("zmax", "contact"))


@pytest.mark.parametrize("thickness, offset, reason", [
    (0.8, 0.0, "a thin body"),
    (10.0, 8.5, "from an edge"),
])
def test_auto_sends_a_thin_layer_and_an_edge_to_the_full_path(thickness, offset, reason):
    """``method = "auto"``: a layer 1.2 contact widths thick and a contact 2.2
    widths from the block's edge fail their geometric applicability checks
    and their corrections' estimates (measured 4.9e-2 and 2.2e-2, against
    3e-3), so the full path solves them, and the line says why.  (Measured:
    2.5 mm thick, 3.7 widths, is refused too, by its thickness alone; 6.5 mm
    from the centre, 5.2 widths from the edge, is solved on the grid.)"""
    result, note = on_grid(_on_layer(thickness, offset), (), "auto", SolverOptions())
    assert result is None
    assert note.startswith('contact.method = "auto": the full path (') and reason in note
    assert "error estimate" in note


def test_auto_solves_resolved_meshes_as_meshed_and_coarse_ones_on_the_grid():
    """``method = "auto"`` (the default): the Hertz example's meshes (0.1 mm
    at the contact, 4.7 element diameters per contact half-width) resolve
    the contact, so the full path solves it as meshed, decided by the grid's
    sizing pass alone; the same bodies meshed at 0.5 mm (one element per
    half-width) go to the grid. Two cubes touching over a whole face have no
    bounded contact zone: the full path, said so."""
    fine = cases.sphere_on_block(0.1, 0.03, friction_coefficient=0.0)
    result, note = on_grid(fine, (), "auto", SolverOptions())
    assert result is None and "the meshes resolve the contact (4.7 elements" in note
    result, note = on_grid(coarse_sphere_on_block(), (), "auto", SolverOptions())
    assert result is not None and note.startswith('contact.method = "auto": the contact grid')
    from bemcontact.mesh import box

    lower = ElasticBody(box((0, 0, 0), (2, 2, 2), 3), STEEL,
                        {"zmin": Displacement((0, 0, 0))}, name="lower")
    upper = ElasticBody(box((0, 0, 2), (2, 2, 4), 3), STEEL,
                        {"zmax": Displacement((0, 0, -0.01))}, name="upper")
    cubes = ContactProblem(lower, upper, ContactPair("zmax", "zmin"))
    result, note = on_grid(cubes, (), "auto", SolverOptions())
    assert result is None and "not concentrated" in note


def test_a_floating_body_is_refused():
    """A sphere held by nothing in x and y (its base pushed in z only) has a
    singular correction problem: refused in one line naming it."""
    prob = coarse_sphere_on_block()
    sphere = prob.bodies[1]
    free = ElasticBody(sphere.mesh, STEEL, {"base": Displacement((None, None, -0.03))},
                       name="sphere")
    with pytest.raises(ConfigError, match="sphere: nothing holds it in x, y"):
        solve_on_grid(ContactProblem(prob.bodies[0], free, ContactPair("zmax", "contact")))


def test_a_frictionless_first_step_in_increments_ends_where_one_increment_does():
    """Without friction the contact does not depend on the path: a first step
    of three increments (the secant predictor starts at the third, from the
    first two; the unloaded start has no solution to extrapolate from) ends
    at the force of one increment, to the Newton tolerance's resolution
    (1e-8: both solve the same equations to 1e-10 of the traction scale)."""
    from bemcontact.contact import LoadStep
    from bemcontact.multiscale.pair import GridOptions

    problem = coarse_sphere_on_block()
    opt = GridOptions(grid_size=0.05)
    once = solve_on_grid(problem, [LoadStep()], opt).history[-1].force[2]
    thrice = solve_on_grid(problem, [LoadStep(increments=3)], opt)
    assert len(thrice.records) == 3 and thrice.converged
    assert thrice.history[-1].force[2] == pytest.approx(once, rel=1e-8)


def test_auto_sends_a_sphere_meshed_too_coarsely_for_its_near_field_to_the_full_path():
    """The benchmark's sphere meshed at 0.8 mm near the contact (elements of
    0.70 near-field radii on the grid of a/12) carries 4 % less force than
    converged, at 0.5 mm (0.48 radii) 0.05 %: the element check (bound 0.6)
    sends the first to the full path, its line saying to refine, and keeps
    the second on the grid."""
    from bemcontact.multiscale.pair import LIMITS

    def sphere(fine):
        return cases.sphere_on_block(fine, 0.03, friction_coefficient=0.0,
                                     setup=cases.SphereOnBlock(fine_radius=1.0, growth=0.45))

    result, note = on_grid(sphere(0.8), (), "auto", SolverOptions())
    assert result is None
    assert "a curved contact face meshed too coarsely for its near field" in note
    assert "refine it near the contact" in note
    res = solve_on_grid(sphere(0.5))
    check = applicability(res, sphere(0.5))["checks"]["element_over_near_radius"]
    assert check["holds"] and check["value"] < LIMITS["element_over_near_radius"] - 0.1


@pytest.mark.parametrize("exc", [np.linalg.LinAlgError("singular matrix"),
                                 scipy.spatial.QhullError("flat"),
                                 ValueError("no points")])
def test_what_the_fits_raise_is_one_line_naming_the_full_path(monkeypatch, exc):
    """A pair and an assembly on the grid (one helper): an error of the fits
    of the contact's geometry becomes a one-line ConfigError at
    contact.method naming method = "full"; bemcontact's own pass as raised."""
    from bemcontact.multiscale import assembly, pair

    def raising(error):
        def solve(*args):
            raise error
        return solve

    for module, name, solve in ((pair, "_solve_on_grid", pair.solve_on_grid),
                                (assembly, "_solve", assembly.solve_assembly_on_grid)):
        monkeypatch.setattr(module, name, raising(exc))
        with pytest.raises(ConfigError) as info:
            solve(None)
        assert str(info.value) == (
            f"method = \"multiscale\": the contact's geometry could not be fitted "
            f"({type(exc).__name__}: {exc}); use method = \"full\"")
        assert info.value.location == {"field": "contact.method"}
        assert info.value.__cause__ is exc
        own = ConfigError("its own")
        monkeypatch.setattr(module, name, raising(own))
        with pytest.raises(ConfigError) as info:
            solve(None)
        assert info.value is own
