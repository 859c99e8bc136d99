"""Bodies far from the origin through the Python API (contact/origin.py):
ContactProblem solves relative to the bodies' own origin and returns the
results at their position, so a rigid offset of the whole problem, 1e12
here, changes nothing (solved at their absolute coordinates, two cubes
offset so would lose 0.5 % of the normal force and every frame state)."""

from __future__ import annotations

import numpy as np
import pytest

import bemcontact as bc

E, NU, MU, P = 1e4, 0.3, 0.2, 400.0
#: every node of 4 and 2 divisions of a 2-cube lies on a grid of 0.5, exact
#: at 1e12 (ulp 1.2e-4): the offset problem's nodes are the original's + offset
OFFSETS = [(1e12, 1e12, 1e12), (-1e12, 3e11, 0.0)]


def _problem(offset=(0.0, 0.0, 0.0), seen=None):
    o = np.asarray(offset, dtype=float)

    def clamp(X):  # a condition given as a function of position
        if seen is not None:
            seen.append(X.copy())
        return np.zeros_like(X)

    lower = bc.ElasticBody(bc.box(o, o + (2, 2, 2), 4), bc.LinearElastic(E, NU),
                           {"zmin": bc.Displacement(clamp)}, name="lower")
    upper = bc.ElasticBody(
        bc.box(o + (0, 0, 2), o + (2, 2, 4), 2), bc.LinearElastic(E, NU),
        {"zmax": [bc.Force((0.0, None, -P)), bc.Displacement((None, 0.0, None))]},
        name="upper")
    return bc.ContactProblem(lower, upper, bc.ContactPair("zmax", "zmin", MU))


STEPS = [bc.LoadStep(label="press"),
         bc.LoadStep({"upper": {"zmax": [bc.Force((0.3 * MU * P, None, -P)),
                                         bc.Displacement((None, 0.0, None))]}},
                     increments=2, label="shear")]


@pytest.fixture(scope="module")
def at_origin():
    return _problem().solve(steps=STEPS)


def _same(r, r0, offset, prob):
    f0 = np.linalg.norm(r0.contact_force)
    assert np.abs(r.contact_force - r0.contact_force).max() < 1e-9 * f0, (
        r.contact_force, r0.contact_force)
    assert abs(r.normal_force - r0.normal_force) < 1e-9 * abs(r0.normal_force)
    assert np.array_equal(r.frame.state, r0.frame.state)
    assert np.array_equal(r.frame.points, r0.frame.points + offset)
    for a, b in zip(r.interfaces, r0.interfaces):
        assert np.array_equal(a.state, b.state)
        assert np.array_equal(a.points, b.points + offset)
    for a, b, body in zip(r.bodies, r0.bodies, prob.bodies):
        assert a.discretization.mesh is body.mesh  # the user's mesh, not the translated one
        assert np.array_equal(a.points, b.points + offset)
        assert np.abs(a.displacement - b.displacement).max() < 1e-9 * np.abs(b.displacement).max()


@pytest.mark.parametrize("offset", OFFSETS)
def test_an_offset_of_1e12_through_contact_problem_changes_nothing(at_origin, offset):
    seen: list = []
    prob = _problem(offset, seen)
    assert np.array_equal(prob.origin, offset)
    assert _problem().origin is None
    r = prob.solve(steps=STEPS)
    assert len(r.history) == 2
    _same(r, at_origin, offset, prob)
    for h, h0 in zip(r.history, at_origin.history):
        _same(h, h0, offset, prob)
    # the callable condition saw the user's points (the lower body's base)
    assert seen and all(np.allclose(X[:, 2], offset[2]) and X[:, 0].min() >= offset[0]
                        and X[:, 0].max() <= offset[0] + 2 for X in seen)


def test_condense_and_re_solve_far_away(at_origin):
    """condense / solve(condensed=) translate too: a re-solve of the offset
    problem from its condensation equals the solve at the origin."""
    offset = OFFSETS[1]
    prob = _problem(offset)
    cond = prob.condense(steps=STEPS)
    assert np.abs(cond.frame.points).max() < 10  # the frame of the translated bodies
    other = _problem(offset)  # another problem object with the same bodies
    r = other.solve(steps=STEPS, condensed=cond)
    _same(r, at_origin, offset, other)


def test_a_failed_solve_far_away_reports_the_bodies_position():
    """ConvergenceError's result is translated back (frictionless and free
    to slide: singular)."""
    o = np.array([1e12, 0.0, 0.0])
    lower = bc.ElasticBody(bc.box(o, o + (2, 2, 2), 4), bc.LinearElastic(E, NU),
                           {"zmin": bc.Fixed()}, name="lower")
    upper = bc.ElasticBody(bc.box(o + (0, 0, 2), o + (2, 2, 4), 2), bc.LinearElastic(E, NU),
                           {"zmax": bc.Displacement((None, None, -0.04))}, name="upper")
    prob = bc.ContactProblem(lower, upper, bc.ContactPair("zmax", "zmin", 0.0))
    with pytest.raises(bc.ConvergenceError) as info:
        prob.solve()
    points = info.value.result.frame.points
    assert points[:, 0].min() == 1e12 and points[:, 0].max() == 1e12 + 2
