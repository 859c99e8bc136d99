"""Principal stresses, von Mises and Tresca (halfspace/measure.py) on states
whose values are known in closed form."""

from __future__ import annotations

import math

import numpy as np
import pytest

from bemcontact.errors import ConfigError
from bemcontact.halfspace import principal_stresses, stress_tensors, tresca, von_mises


def _rotation(angles):
    a, b, c = angles
    rz = np.array([[math.cos(a), -math.sin(a), 0], [math.sin(a), math.cos(a), 0], [0, 0, 1]])
    ry = np.array([[math.cos(b), 0, math.sin(b)], [0, 1, 0], [-math.sin(b), 0, math.cos(b)]])
    rx = np.array([[1, 0, 0], [0, math.cos(c), -math.sin(c)], [0, math.sin(c), math.cos(c)]])
    return rz @ ry @ rx


def _components(tensor):
    return tensor[..., [0, 1, 2, 0, 1, 0], [0, 1, 2, 1, 2, 2]]


def test_rotated_diagonal_states():
    """A diagonal state (σ1, σ2, σ3) seen in rotated axes: the principal
    stresses come back sorted σ1 ≥ σ2 ≥ σ3, von Mises is
    √(½[(σ1 − σ2)² + (σ2 − σ3)² + (σ3 − σ1)²]) and the maximum shear
    (σ1 − σ3)/2, whatever the axes (an eigenvalue problem and an invariant,
    exact to round-off: 1e-12 of the stress)."""
    rng = np.random.default_rng(5)
    principal = np.array([[3.0, -1.0, 0.5], [-2.0, -2.0, 1.0], [0.0, 4.0, 4.0]])
    states = []
    for p in principal:
        r = _rotation(rng.uniform(0, 2 * math.pi, 3))
        states.append(_components(r @ np.diag(p) @ r.T))
    states = np.array(states).reshape(3, 1, 6)  # any leading shape
    got = principal_stresses(states)
    assert got.shape == (3, 1, 3)
    assert np.abs(got[:, 0] - np.sort(principal, axis=1)[:, ::-1]).max() < 1e-12 * 4
    s1, s2, s3 = principal.T
    mises = np.sqrt(0.5 * ((s1 - s2) ** 2 + (s2 - s3) ** 2 + (s3 - s1) ** 2))
    assert np.abs(von_mises(states)[:, 0] - mises).max() < 1e-12 * 4
    shear = 0.5 * (principal.max(axis=1) - principal.min(axis=1))
    assert np.abs(tresca(states)[:, 0] - shear).max() < 1e-12 * 4


def test_textbook_states():
    """Uniaxial σ: von Mises σ, maximum shear σ/2; pure shear τ: von Mises
    √3 τ, maximum shear τ; hydrostatic: both zero (exact in floating point
    up to the eigenvalue round-off, 1e-14 of the stress)."""
    uniaxial = np.array([2.0, 0, 0, 0, 0, 0])
    shear = np.array([0, 0, 0, 0, 0, 1.5])  # σ_xz
    hydro = np.array([-3.0, -3.0, -3.0, 0, 0, 0])
    assert von_mises(uniaxial) == pytest.approx(2.0, rel=1e-14)
    assert tresca(uniaxial) == pytest.approx(1.0, rel=1e-14)
    assert von_mises(shear) == pytest.approx(math.sqrt(3.0) * 1.5, rel=1e-14)
    assert tresca(shear) == pytest.approx(1.5, rel=1e-14)
    assert principal_stresses(shear) == pytest.approx([1.5, 0.0, -1.5], abs=1e-14)
    assert abs(von_mises(hydro)) < 1e-14 and abs(tresca(hydro)) < 1e-14
    t = stress_tensors(np.array([1.0, 2, 3, 4, 5, 6]))
    assert t.tolist() == [[1, 4, 6], [4, 2, 5], [6, 5, 3]]


@pytest.mark.parametrize("func", [principal_stresses, von_mises, tresca, stress_tensors])
def test_wrong_shape_is_rejected(func):
    with pytest.raises(ConfigError, match=r"stresses must have shape \(\.\.\., 6\)"):
        func(np.zeros((4, 3)))
