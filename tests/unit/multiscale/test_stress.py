"""Stresses on the multiscale path: the half-space field of the grid
tractions below each body's own contact surface."""

from __future__ import annotations

import numpy as np
import pytest

from bemcontact.errors import ConfigError
from bemcontact.multiscale.pair import solve_on_grid
from bemcontact.validation import cases
from bemcontact.validation.reference import contact as ref

NU = 0.3


@pytest.fixture(scope="module")
def hertz_on_grid():
    """The frictionless sphere on the block, coarse bodies, grid of a/25."""
    return solve_on_grid(cases.sphere_on_block(0.5, 0.03, friction_coefficient=0.0,
                                               setup=cases.SphereOnBlock()))


def _johnson(z):
    """σ_z, σ_r / p0 on the axis below a frictionless Hertz contact (Johnson §3.4)."""
    return (-1.0 / (1.0 + z * z),
            -(1.0 + NU) * (1.0 - z * np.arctan(1.0 / z)) + 0.5 / (1.0 + z * z))


def test_the_axis_stresses_of_both_bodies_match_hertz(hertz_on_grid):
    """Below the contact's centre in the block (body 1, below the frame) and
    in the sphere (body 2, above it, depths measured from its curved
    surface), σ_z and σ_r within 0.5 % of p0 of Johnson's closed forms for
    0.05a <= z <= 3a, with a and p0 of Hertz for the grid's force: the
    piecewise-constant tractions on cells of a/24 (measured 0.12 %; the
    grid's own p0 is within 0.1 % of Hertz, docs/validation.md).  The two
    bodies are mirror images: the same σ_z to 1e-9 p0 at the same depth."""
    res = hertz_on_grid
    P = res.history[-1].force[2]
    h = ref.hertz(P, 10.0, cases.SphereOnBlock().contact_modulus)
    a, p0 = h.contact_radius, h.peak_pressure
    z = np.linspace(0.05, 3.0, 30)
    c = res.origin
    # each body's surface height ζ(0, 0) above the frame's plane (its quartic's constant)
    zeta1, zeta2 = (float(s[0]) for s in res.surfaces)
    below = np.column_stack([np.full_like(z, c[0]), np.full_like(z, c[1]), c[2] + zeta1 - z * a])
    sz, sr = _johnson(z)
    s1 = res.stresses("block", below)
    assert np.abs(s1[:, 2] / p0 - sz).max() < 5e-3
    assert np.abs(s1[:, 0] / p0 - sr).max() < 5e-3 and np.abs(s1[:, 1] / p0 - sr).max() < 5e-3
    # the sphere: the same depths below its own surface (ζ2(0, 0) above the plane)
    above = below * [1, 1, 0] + np.column_stack([np.zeros((30, 2)), c[2] + zeta2 + z * a])
    s2 = res.stresses("sphere", above)
    assert np.abs(s2[:, 2] - s1[:, 2]).max() < 1e-9 * p0


def test_points_outside_a_body_or_unknown_bodies_are_refused(hertz_on_grid):
    res = hertz_on_grid
    with pytest.raises(ConfigError, match="not inside body 'block'"):
        res.stresses("block", [[0.0, 0.0, 0.01]])
    with pytest.raises(ConfigError, match="unknown body"):
        res.stresses("cube", [[0.0, 0.0, -0.1]])
    with pytest.raises(ConfigError, match="step must index"):
        res.stresses("block", [[0.0, 0.0, -0.1]], step=3)


def test_the_tension_at_the_contact_edge_on_the_grid_matches_hertz(hertz_on_grid):
    """The block's surface radial stress at the grid cells (the half-space
    field's limit at the surface): its largest value, just outside the
    contact edge, within 5 % of Johnson's (1 − 2ν)p0/3 (measured −2.9 % at
    cells of a/24, −1.5 % at a/48: the cell nearest the edge from outside);
    at the centre σ_r = −(1 + 2ν)p0/2 and σ_z = −p0 within 0.5 % of p0
    (the centre cell's pressure; measured 0.12 %); and the two bodies'
    surfaces carry the same normal stress σ_zz (the traction, to round-off)."""
    from bemcontact.multiscale.stress import grid_surface_points

    res = hertz_on_grid
    P = res.history[-1].force[2]
    h = ref.hertz(P, 10.0, cases.SphereOnBlock().contact_modulus)
    a, p0 = h.contact_radius, h.peak_pressure
    s = res.surface_stresses("block")
    X = grid_surface_points(res, "block") - res.origin
    r = np.hypot(X[:, 0], X[:, 1])
    c, d = X[:, 0] / np.maximum(r, 1e-300), X[:, 1] / np.maximum(r, 1e-300)
    sr = s[:, 0] * c * c + s[:, 1] * d * d + 2.0 * s[:, 3] * c * d
    k = int(np.argmax(sr))
    assert abs(sr[k] / p0 / ((1.0 - 2.0 * NU) / 3.0) - 1.0) < 0.05
    assert 1.0 <= r[k] / a <= 1.1
    centre = int(np.argmin(r))
    assert abs(s[centre, 0] / p0 + (1.0 + 2.0 * NU) / 2.0) < 5e-3
    assert abs(s[centre, 2] / p0 + 1.0) < 5e-3
    assert np.allclose(res.surface_stresses("sphere")[:, 2], s[:, 2], rtol=0, atol=1e-9 * p0)
