"""Bodies far from the origin through a problem file: ContactProblem
solves relative to the bodies' own origin (bemcontact.contact.origin), so a
rigid offset of the whole problem, 1e12 here, changes nothing (solved at
their absolute coordinates, two cubes offset so would lose 0.5 % of the
normal force and every frame state)."""

from __future__ import annotations

import json

import meshio
import numpy as np
import pytest

import bemcontact as bc
from bemcontact.cli import main

from ..test_cli import ROOT

EXAMPLE = (ROOT / "examples" / "two_cubes_similar.toml").read_text()


def _cubes(tmp_path, offset, divisions=(4, 2), name="cubes.toml", mu="0.1"):
    """The example's two cubes, translated by ``offset``; divisions 4 and 2
    put every node on a grid of 0.5, exact at 1e12 (ulp 1.2e-4), so the
    offset problem's nodes are exactly the original's plus the offset."""
    ox, oy, oz = offset
    s = EXAMPLE.replace("divisions = 6", f"divisions = {divisions[0]}")
    s = s.replace("divisions = 5", f"divisions = {divisions[1]}")
    s = s.replace("friction_coefficient = 0.1", f"friction_coefficient = {mu}")
    for z in (0, 2):
        old = f"lower = [0, 0, {z}], upper = [2, 2, {z + 2}]"
        assert old in s
        s = s.replace(old, f"lower = [{ox!r}, {oy!r}, {oz + z!r}], "
                           f"upper = [{ox + 2!r}, {oy + 2!r}, {oz + z + 2!r}]")
    path = tmp_path / name
    path.write_text(s)
    return path


@pytest.fixture(scope="module")
def at_origin(tmp_path_factory):
    return bc.load_problem(_cubes(tmp_path_factory.mktemp("o"), (0.0, 0.0, 0.0))).solve()


@pytest.mark.parametrize("offset", [(1e12, 1e12, 1e12), (0.0, 0.0, 1e12), (-1e12, 3e11, 0.0)])
def test_an_offset_of_1e12_changes_nothing(tmp_path, at_origin, offset):
    pf = bc.load_problem(_cubes(tmp_path, offset))
    assert pf.origin is not None and np.array_equal(pf.origin, offset)
    r = pf.solve()
    f0 = np.linalg.norm(at_origin.contact_force)
    assert np.abs(r.contact_force - at_origin.contact_force).max() < 1e-9 * f0
    assert abs(r.normal_force - at_origin.normal_force) < 1e-9 * abs(at_origin.normal_force)
    assert np.array_equal(r.frame.state, at_origin.frame.state)
    for a, b in zip(r.interfaces, at_origin.interfaces):
        assert np.array_equal(a.state, b.state)
        assert np.array_equal(a.points, b.points + offset)  # reported where the bodies are
    assert np.array_equal(r.frame.points, at_origin.frame.points + offset)
    for a, b, body in zip(r.bodies, at_origin.bodies, pf.bodies):
        assert a.discretization.mesh is body.mesh
        assert np.array_equal(a.points, b.points + offset)
        assert np.array_equal(a.displacement, b.displacement)
    assert r.history[-1] is r


def test_the_written_files_are_at_the_bodies_position(tmp_path, at_origin):
    offset = (-1e12, 3e11, 0.0)
    out = tmp_path / "out"
    assert main(["run", str(_cubes(tmp_path, offset)), "--out", str(out), "--quiet"]) == 0
    lower = meshio.read(out / "lower.vtu").points
    assert np.array_equal(lower.min(axis=0), offset)
    assert np.array_equal(lower.max(axis=0), np.add(offset, 2.0))
    s = json.loads((out / "summary.json").read_text())
    assert abs(s["normal_force"] - at_origin.normal_force) < 1e-9 * at_origin.normal_force


def test_the_example_far_away_agrees_to_its_input_rounding(tmp_path):
    """The example's own meshes (6 and 5 divisions: nodes at thirds and
    fifths, rounded at 1e12 to 1.2e-4): the offset moves nodes by up to 6e-5
    of 0.33, and the force by as little (solved at the absolute coordinates
    it moves by 0.5 %)."""
    r0 = bc.load_problem(_cubes(tmp_path, (0.0, 0.0, 0.0), (6, 5), "a.toml")).solve()
    r1 = bc.load_problem(_cubes(tmp_path, (1e12, 1e12, 0.0), (6, 5), "b.toml")).solve()
    assert abs(r1.normal_force / r0.normal_force - 1) < 1e-4, (r0.normal_force, r1.normal_force)
    assert np.array_equal(r1.frame.state, r0.frame.state)


def test_near_the_origin_the_bodies_are_solved_as_given(tmp_path):
    assert bc.load_problem(_cubes(tmp_path, (0.0, 0.0, 0.0))).origin is None
    assert bc.load_problem(_cubes(tmp_path, (10.0, -5.0, 3.0))).origin is None  # < 8 sizes


def test_a_failed_solve_far_away_reports_the_bodies_position(tmp_path):
    """ConvergenceError's result is translated back too (frictionless and
    free to slide: singular)."""
    path = _cubes(tmp_path, (1e12, 0.0, 0.0), mu="0")
    path.write_text(path.read_text().replace("displacement = [0, 0, -0.04]",
                                             'displacement = ["free", "free", -0.04]'))
    with pytest.raises(bc.ConvergenceError) as info:
        bc.load_problem(path).solve()
    points = info.value.result.frame.points
    assert points[:, 0].min() == 1e12 and points[:, 0].max() == 1e12 + 2


def test_signed_volume_far_from_the_origin():
    """A 2 x 2 x 2 box at -1e12 has volume 8 and passes the check: x in
    V = 1/3 ∮ x.n dS is taken from a node (the absolute x cancels to -1.9e6,
    which would call the box inverted; the quadrature points themselves are
    rounded to 1.2e-4 there)."""
    far = bc.box((-1e12, 3e11, 0), (-1e12 + 2, 3e11 + 2, 2), 4)
    assert far.check() is far
    assert far.signed_volume() == pytest.approx(8.0, rel=1e-4)
