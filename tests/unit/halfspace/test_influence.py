"""Love's rectangle integrals and the influence blocks (halfspace/influence.py)
against the Boussinesq–Cerruti point loads, the closed form at the centre of a
square, and the two-body operator built from two mirrored half-spaces."""

from __future__ import annotations

import math

import numpy as np
import pytest

from bemcontact.errors import ConfigError
from bemcontact.halfspace import Compliance, influence_blocks, rectangle_integrals

G, NU = 80.0, 0.3
E = 2.0 * G * (1.0 + NU)


def point_load(x: float, y: float, shear_modulus: float, poisson_ratio: float) -> np.ndarray:
    """Surface displacement at (x, y) of a half-space z > 0 under a unit point
    force at the origin (columns: force along x, y, z; z into the body), from
    Johnson, Contact Mechanics (1985), ch. 3, at z = 0: the normal
    force draws the surface towards itself, a tangential force pushes the
    surface ahead of it into the body."""
    g, nu = shear_modulus, poisson_ratio
    r = math.hypot(x, y)
    c = 1.0 / (2.0 * math.pi * g)
    d = (1.0 - 2.0 * nu) / (4.0 * math.pi * g)
    return np.array([
        [c * ((1 - nu) / r + nu * x * x / r**3), c * nu * x * y / r**3, -d * x / r**2],
        [c * nu * x * y / r**3, c * ((1 - nu) / r + nu * y * y / r**3), -d * y / r**2],
        [d * x / r**2, d * y / r**2, c * (1 - nu) / r],
    ])


OFFSETS = [(20, 0), (0, 20), (20, 13), (-14, -20)]


@pytest.mark.parametrize("offset", OFFSETS)
def test_far_cells_approach_the_point_load(offset):
    """A cell ≥ 20 cells away acts as a point force of the same total (dx dy
    times the traction), to second order in h/r: the rectangle integral is the
    midpoint rule plus (dx² ∂xx + dy² ∂yy)/24 of the kernel, which for kernels
    homogeneous of degree −1 is at most ~(h/r)²/6 of the block (observed
    0.03–0.06 (h/r)² block-wise, ≤ 0.082 (h/r)² for each component above a tenth
    of the block's largest).  Doubling the distance divides the error by 4
    (observed 4.00; the next term is O((h/r)⁴))."""
    dx, dy = 0.3, 0.2  # unequal, so a swap of x and y shows
    h = max(dx, dy)
    blocks = influence_blocks(81, 81, dx, dy, Compliance.half_space(G, NU))
    errors = []
    for scale in (1, 2):
        i, j = offset[0] * scale, offset[1] * scale
        block = blocks[i + 80, j + 80]
        point = point_load(i * dx, j * dy, G, NU) * dx * dy
        r = math.hypot(i * dx, j * dy)
        size = np.abs(point).max()
        err = np.abs(block - point).max() / size
        assert err < 0.25 * (h / r) ** 2, (offset, scale, err)
        big = np.abs(point) > 0.1 * size
        per_component = np.abs(block - point)[big] / np.abs(point)[big]
        assert per_component.max() < 0.25 * (h / r) ** 2, (offset, scale, per_component)
        errors.append(err)
    assert 3.8 < errors[0] / errors[1] < 4.2, errors


def test_normal_force_draws_the_surface_towards_it():
    """Boussinesq: under a pressure the surface beside the load moves towards
    it (u_x < 0 at x > 0) and into the body (u_z > 0); by reciprocity a shear
    in +x pushes the surface ahead of it into the body."""
    blocks = influence_blocks(3, 3, 1.0, 1.0, Compliance.half_space(G, NU))
    right = blocks[2 + 1, 2]  # observation cell one to the right (+x) of the load
    assert right[0, 2] < 0 and right[2, 2] > 0 and right[2, 0] > 0


@pytest.mark.parametrize("nu", [0.0, 0.3, 0.49, -0.5])
def test_centre_of_a_uniformly_loaded_square(nu):
    """Johnson §3.2 (Love): at the centre of a square of side 2c under a
    uniform pressure p, u_z = (1 − ν²)/(πE) · p · 4c · 2 ln(1 + √2) (the
    integral of 1/r over the square is 8c ln(1 + √2)); a uniform shear q gives
    u_x = q/(2πG) [(1 − ν) + ν/2] · 8c ln(1 + √2) (x²/r³ over the square is
    half of 1/r).  The formulas are the same closed form, evaluated
    differently, so they agree to round-off: 1e-12 (observed ≤ 4e-16)."""
    c, p = 0.7, 3.0
    e_modulus = 2.0 * G * (1.0 + nu)
    log_term = 2.0 * math.log(1.0 + math.sqrt(2.0))
    expected_uz = (1.0 - nu**2) / (math.pi * e_modulus) * p * 4.0 * c * log_term
    expected_ux = p / (2.0 * math.pi * G) * (1.0 - nu / 2.0) * 4.0 * c * log_term
    block = influence_blocks(1, 1, 2 * c, 2 * c, Compliance.half_space(G, nu))[0, 0]
    assert block[2, 2] * p == pytest.approx(expected_uz, rel=1e-12)
    assert block[0, 0] * p == pytest.approx(expected_ux, rel=1e-12)
    assert block[1, 1] * p == pytest.approx(expected_ux, rel=1e-12)
    integrals = rectangle_integrals(0.0, 0.0, c, c)
    assert integrals[0] + integrals[1] == pytest.approx(4.0 * c * log_term, rel=1e-12)
    # the self-coefficient has no coupling: odd integrands over a symmetric cell
    off = block[[0, 0, 1, 1, 2, 2], [1, 2, 0, 2, 0, 1]]
    assert np.abs(off).max() < 1e-14 * block[2, 2]


def test_lattice_blocks_equal_the_pointwise_integrals():
    """influence_blocks differences the corner antiderivatives on one lattice;
    rectangle_integrals evaluates each cell on its own: the same sums in another
    order, to round-off (1e-12 of the block; observed 1e-16)."""
    dx, dy = 0.5, 1.25
    c = Compliance.pair(30.0, 0.2, 70.0, 0.35)
    blocks = influence_blocks(6, 4, dx, dy, c)
    i, j = np.meshgrid(np.arange(-5, 6), np.arange(-3, 4), indexing="ij")
    integrals = rectangle_integrals(i * dx, j * dy, dx / 2, dy / 2)
    S, T, K = c.isotropic, c.tangential, c.difference
    one_over_r = integrals[0] + integrals[1]
    assert np.allclose(blocks[..., 2, 2], S * one_over_r / (2 * math.pi), rtol=1e-12, atol=0)
    assert np.allclose(blocks[..., 0, 1], T * integrals[2] / (2 * math.pi),
                       rtol=0, atol=1e-12 * blocks[5, 3, 2, 2])
    assert np.allclose(blocks[..., 0, 2], K * integrals[3] / math.pi,
                       rtol=0, atol=1e-12 * blocks[5, 3, 2, 2])


def test_two_bodies_are_body_2_minus_mirrored_body_1():
    """The pair operator is u_2 − u_1: body 2 is the half-space z > 0 under λ;
    body 1, on z < 0 under −λ, is a half-space seen through the rotation R =
    diag(1, −1, −1) about x (its own z into it, right-handed), so its block at
    offset (x, y) is −R B_1(x, −y) R and u_2 − u_1 = B_2 + R B_1(x, −y) R.
    The coupling is K = ¼ [(1 − 2ν_1)/G_1 − (1 − 2ν_2)/G_2]; the same sums in
    another order, so to round-off (1e-13 of the largest entry; observed 2e-16)."""
    g1, nu1, g2, nu2 = 30.0, 0.1, 70.0, 0.45
    nx, ny, dx, dy = 5, 4, 0.4, 0.3
    pair = influence_blocks(nx, ny, dx, dy, Compliance.pair(g1, nu1, g2, nu2))
    body1 = influence_blocks(nx, ny, dx, dy, Compliance.half_space(g1, nu1))
    body2 = influence_blocks(nx, ny, dx, dy, Compliance.half_space(g2, nu2))
    R = np.diag([1.0, -1.0, -1.0])
    expected = body2 + R @ body1[:, ::-1] @ R
    assert np.abs(pair - expected).max() < 1e-13 * np.abs(pair).max()
    K = 0.25 * ((1 - 2 * nu1) / g1 - (1 - 2 * nu2) / g2)
    assert Compliance.pair(g1, nu1, g2, nu2).difference == pytest.approx(K, rel=1e-14)


def test_identical_bodies_do_not_couple():
    """Identical materials: K = 0 exactly in arithmetic, so the normal and
    tangential problems decouple (the coupling blocks vanish against the
    diagonal's scale: 1e-14), and every other term doubles."""
    pair = influence_blocks(4, 4, 1.0, 1.0, Compliance.pair(G, NU, G, NU))
    one = influence_blocks(4, 4, 1.0, 1.0, Compliance.half_space(G, NU))
    scale = np.abs(pair).max()
    assert np.abs(pair[..., 0:2, 2]).max() < 1e-14 * scale
    assert np.abs(pair[..., 2, 0:2]).max() < 1e-14 * scale
    assert np.abs(pair[..., :2, :2] - 2 * one[..., :2, :2]).max() < 1e-14 * scale
    assert np.abs(pair[..., 2, 2] - 2 * one[..., 2, 2]).max() < 1e-14 * scale


def test_composite_moduli():
    """E* = 1/Σ(1 − ν²)/E and Dundurs' β = [G_1 κ_2' − G_2 κ_1'] / [2 G_1 (1 − ν_2)
    + 2 G_2 (1 − ν_1)], κ' = 1 − 2ν: closed forms, so to round-off (1e-14)."""
    g1, nu1, g2, nu2 = 30.0, 0.1, 70.0, 0.45
    c = Compliance.pair(g1, nu1, g2, nu2)
    e1, e2 = 2 * g1 * (1 + nu1), 2 * g2 * (1 + nu2)
    assert c.contact_modulus == pytest.approx(1 / ((1 - nu1**2) / e1 + (1 - nu2**2) / e2),
                                              rel=1e-14)
    beta = (g1 * (1 - 2 * nu2) - g2 * (1 - 2 * nu1)) / (2 * g1 * (1 - nu2) + 2 * g2 * (1 - nu1))
    assert c.dundurs_beta == pytest.approx(beta, rel=1e-14)
    # one body on a rigid one, ν = 0: β = ½ (Spence's largest coupling)
    assert Compliance.half_space(1.0, 0.0).dundurs_beta == pytest.approx(0.5, rel=1e-15)


@pytest.mark.parametrize("call, match", [
    (lambda: Compliance.half_space(0.0, 0.3), "shear_modulus must be > 0, got 0.0"),
    (lambda: Compliance.half_space(-1.0, 0.3), "shear_modulus must be > 0"),
    (lambda: Compliance.half_space(math.nan, 0.3), "shear_modulus must be finite"),
    (lambda: Compliance.half_space(1.0, 0.5), r"poisson_ratio must be in \(-1, 0.5\), got 0.5"),
    (lambda: Compliance.half_space(1.0, -1.0), "poisson_ratio must be in"),
    (lambda: Compliance.half_space("steel", 0.3), "shear_modulus must be a number"),
    (lambda: Compliance.pair(1.0, 0.3, -2.0, 0.3), "shear_modulus_2 must be > 0"),
    (lambda: Compliance.pair(1.0, 0.6, 2.0, 0.3), "poisson_ratio_1 must be in"),
    (lambda: Compliance(0.0, 0.1, 0.0), "isotropic must be > 0"),
    (lambda: Compliance(1.0, math.inf, 0.0), "tangential must be a finite number"),
    (lambda: influence_blocks(0, 3, 1.0, 1.0, Compliance.half_space(1, 0)),
     "nx must be an integer >= 1, got 0"),
    (lambda: influence_blocks(3, 2.5, 1.0, 1.0, Compliance.half_space(1, 0)),
     "ny must be an integer"),
    (lambda: influence_blocks(3, 3, 0.0, 1.0, Compliance.half_space(1, 0)), "dx must be > 0"),
    (lambda: influence_blocks(3, 3, 1.0, math.inf, Compliance.half_space(1, 0)),
     "dy must be finite"),
    (lambda: influence_blocks(3, 3, 1.0, 1.0, "steel"), "compliance must be a Compliance"),
    (lambda: rectangle_integrals(0.0, 0.0, 0.0, 1.0), "half_width_x must be > 0"),
])
def test_bad_input_names_the_field(call, match):
    with pytest.raises(ConfigError, match=match):
        call()
