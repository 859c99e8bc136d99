"""Each body's fields on its own coarse mesh after a grid solve, by
superposition (multiscale/result.py ``GridResult.body_fields`` and
``reactions``; multiscale/correction.py ``BodyCorrection.fields``), against
the full path on finely meshed bodies."""

from __future__ import annotations

import math

import numpy as np
import pytest

from bemcontact.contact import ContactPair, ContactProblem
from bemcontact.errors import ConfigError
from bemcontact.multiscale.pair import GridOptions, solve_on_grid
from bemcontact.validation import cases

APPROACH = 0.03
A = math.sqrt(10.0 * APPROACH)


@pytest.fixture(scope="module")
def grid_result():
    """The coarse sphere on block (0.5 mm near the contact), frictionless,
    pressed 0.03 mm, on cells of a/8 (the full path's a/h in conftest)."""
    coarse = cases.sphere_on_block(0.5, APPROACH, friction_coefficient=0.0,
                                   setup=cases.SphereOnBlock(fine_radius=1.0, growth=0.45))
    return solve_on_grid(coarse, options=GridOptions(grid_size=A / 8.0))


def _radial(sol, points):
    r = np.hypot(points[:, 0], points[:, 1])
    ur = (sol[:, 0] * points[:, 0] + sol[:, 1] * points[:, 1]) / np.maximum(r, 1e-12)
    return r, ur


@pytest.mark.validation
@pytest.mark.parametrize("body, tangential_bound", [("block", 0.02), ("sphere", 0.07)])
def test_the_contact_face_displacements_match_the_full_path(grid_result,
                                                            full_sphere_on_block_result, body,
                                                            tangential_bound):
    """On each body's contact face within 4 mm of the contact (4a), the
    coarse nodes' displacement against the full path's (both bodies meshed
    at a/8 within 1.1a; its nodal profile interpolated in r: the problem is
    axisymmetric to the square block's far corners).  Measured, largest
    difference over the nodes: the normal displacement 0.27 % (block) and
    0.33 % (sphere) of the body's largest deformation there (its support's
    translation taken off), asserted 0.6 % (the two paths' forces differ by
    0.13 % at a/h = 8, and the profile's interpolation between the full
    path's nodes); the radial displacement 1.1 % (block) and 4.6 % (sphere)
    of its largest value, asserted 2 % and 7 %: the sphere's near its
    contact is the near field's share of the curved face's residual
    traction, applied on the tangent plane (first order in the slope there,
    which reaches 0.1–0.4 at 1–4 mm)."""
    full = full_sphere_on_block_result
    k = full.names.index(body)
    ref = full.bodies[k]
    got = grid_result.body_fields(body)
    shift = grid_result.history[-1].translations[grid_result.names.index(body)]

    def face(P):
        return (np.abs(P[:, 2]) < 1.0) & (np.hypot(P[:, 0], P[:, 1]) < 4.0)

    fr, mr = face(ref.points), face(got.points)
    assert mr.sum() >= 60
    r_ref, ur_ref = _radial(ref.displacement[fr], ref.points[fr])
    r_got, ur_got = _radial(got.displacement[mr], got.points[mr])
    o = np.argsort(r_ref)
    uz_ref = np.interp(r_got, r_ref[o], ref.displacement[fr][o, 2] - shift[2])
    uz_got = got.displacement[mr, 2] - shift[2]
    normal = np.abs(uz_got - uz_ref).max() / np.abs(uz_ref).max()
    ur_at = np.interp(r_got, r_ref[o], ur_ref[o])
    tangential = np.abs(ur_got - ur_at).max() / np.abs(ur_at).max()
    assert normal < 0.006, normal
    assert tangential < tangential_bound, tangential


def test_the_supports_hold_and_their_reactions_carry_the_contact_force(grid_result):
    """Superposed, each body's supports keep their prescribed translation
    (measured: the block to 1.4e-9 mm, the sphere's base to 5.7e-7 mm, the
    near field's share of its residual traction not being cancelled there;
    asserted 5e-5 of the approach), and the reactions on them balance the
    contact force on the body: measured −0.65 % (block) and +1.1 % (sphere)
    of it, asserted 2 % (the coarse mesh's share of the half-space field's
    traction on the free faces near the contact, 0.5 mm elements; without
    those data, the remainder's reactions miss 85 % of the force on the
    block)."""
    res = grid_result
    F = res.history[-1].force @ res.axes  # on body 2 (the sphere), global
    R = res.reactions()
    for b, name in enumerate(res.names):
        sol = res.body_fields(name)
        held = res.corrections[b].held.reshape(-1, 3)
        shift = res.history[-1].translations[b]
        off = np.abs(np.where(held, sol.displacement - shift, 0.0)).max()
        assert off < 5e-5 * APPROACH, (name, off)
        on_body = -F if b == 0 else F
        balance = np.linalg.norm(R[name] + on_body) / np.linalg.norm(F)
        assert balance < 0.02, (name, balance)
    # the traction on the contact face inside the grid is the grid's (on the sphere
    # the pressure pushes it along +z)
    sol = res.body_fields("sphere")
    apex = int(np.argmin(np.linalg.norm(sol.points - res.origin, axis=1)))
    assert sol.traction[apex, 2] > 0.9 * res.history[-1].p[:, 2].max()  # pushed up


def test_the_fields_do_not_depend_on_which_body_is_body_1(grid_result):
    """The same problem with the sphere as body 1 (the frame's normal then
    points down, its local frame mirrored): the same contact force and each
    body's same fields, to the Newton tolerance (measured: P to 4e-12, the
    displacements to 1.6e-9 and the tractions to 1.8e-8 of their largest;
    asserted 1e-6).  Also the contact plane: the sphere's closest node is not
    its apex, so the normal comes from the flatter surface's nodes."""
    block, sphere = cases.sphere_on_block(
        0.5, APPROACH, friction_coefficient=0.0,
        setup=cases.SphereOnBlock(fine_radius=1.0, growth=0.45)).bodies
    swapped = solve_on_grid(ContactProblem(sphere, block, ContactPair("contact", "zmax")),
                            options=GridOptions(grid_size=A / 8.0))
    assert swapped.axes[2] == pytest.approx([0.0, 0.0, -1.0])
    P, P_swapped = grid_result.history[-1].force[2], swapped.history[-1].force[2]
    assert P_swapped == pytest.approx(P, rel=1e-8)
    for name in ("block", "sphere"):
        a, b = grid_result.body_fields(name), swapped.body_fields(name)
        for field in ("displacement", "traction"):
            x, y = getattr(a, field), getattr(b, field)
            assert np.abs(x - y).max() < 1e-6 * np.abs(x).max(), (name, field)


def test_body_fields_refuse_an_unknown_body_or_step(grid_result):
    with pytest.raises(ConfigError, match="unknown body 'ball'"):
        grid_result.body_fields("ball")
    with pytest.raises(ConfigError, match="step must index"):
        grid_result.body_fields("block", 3)
