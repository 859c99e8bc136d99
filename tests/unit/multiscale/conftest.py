"""The full path's sphere-on-block solution that the multiscale tests compare
with (computed once per session: 5.6 s)."""

from __future__ import annotations

import math

import pytest

from bemcontact.validation import cases

#: contact resolution of the full path's reference (elements per contact radius)
A_OVER_H = 8.0


@pytest.fixture(scope="session")
def full_sphere_on_block_result():
    """The full path's ContactResult of the benchmark's frictionless steel
    sphere (R = 10) on a steel block (20 × 20 × 10, base clamped), approach
    0.03 mm, both meshed at h = a/8 within 1.1a of the contact."""
    a_guess = math.sqrt(10.0 * 0.03)
    h = a_guess / A_OVER_H
    fine = cases.SphereOnBlock(size_profile=((0.0, h), (1.1 * a_guess, h)), growth=0.45)
    return cases.sphere_on_block(h, 0.03, friction_coefficient=0.0, setup=fine).solve()


@pytest.fixture(scope="session")
def full_sphere_on_block(full_sphere_on_block_result):
    """(P, radial positions, pressures, h) of that solution."""
    res = full_sphere_on_block_result
    r, p, *_ = cases.radial_profile(res.history[0].frame)
    return res.history[0].normal_force, r, p, math.sqrt(10.0 * 0.03) / A_OVER_H
