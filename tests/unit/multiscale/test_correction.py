"""The finite bodies' correction of the contact grid (multiscale/correction.py):
the point-load fields it subtracts against their closed forms, and a whole
grid solve with the corrections of a coarse sphere and block against the
full path on the same bodies (what the half-space alone misses)."""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.fft

from bemcontact.halfspace import Compliance, Grid
from bemcontact.multiscale import GridInterface, PairOperator
from bemcontact.multiscale.correction import (
    BodyCorrection,
    chebyshev_points,
    lagrange_weights,
    point_load_displacements,
)
from bemcontact.multiscale.pair import LIMITS
from bemcontact.validation import cases

G, NU = 80.0, 0.3


def test_point_loads_on_the_surface_are_the_grid_kernels():
    """At z = 0 the Boussinesq and Cerruti displacements are the surface
    kernels of halfspace/influence.py (one body: S = (1 − ν)/G, T = ν/G, K =
    −(1 − 2ν)/(4G)), to round-off."""
    X = np.array([[1.3, -0.4, 0.0], [-0.2, 2.1, 0.0]])
    u = point_load_displacements(X, G, NU)
    S, T, K = (1 - NU) / G, NU / G, -(1 - 2 * NU) / (4 * G)
    for (x, y, _), ui in zip(X, u):
        r = math.hypot(x, y)
        C = np.array([[S / r + T * x * x / r**3, T * x * y / r**3, 2 * K * x / r**2],
                      [T * x * y / r**3, S / r + T * y * y / r**3, 2 * K * y / r**2],
                      [-2 * K * x / r**2, -2 * K * y / r**2, S / r]]) / (2 * math.pi)
        assert np.allclose(ui, C, rtol=1e-13, atol=0.0)


def test_point_load_below_the_axis():
    """On the axis below a normal force, u_z = (3 − 2ν) / (4πG z) and the
    lateral components vanish (Johnson §3.2)."""
    z = np.array([0.5, 2.0])
    u = point_load_displacements(np.stack([0 * z, 0 * z, z], axis=1), G, NU)
    assert np.allclose(u[:, 2, 2], (3 - 2 * NU) / (4 * math.pi * G * z), rtol=1e-14)
    assert np.abs(u[:, :2, 2]).max() == 0.0


def test_chebyshev_interpolation_reproduces_polynomials():
    """The anchors' Lagrange weights reproduce a polynomial of degree p − 1
    exactly (to round-off) and sum to one."""
    nodes = chebyshev_points(4)
    t = np.linspace(-1.0, 1.0, 7)
    L = lagrange_weights(nodes, t)
    assert np.allclose(L.sum(axis=1), 1.0, rtol=0, atol=1e-14)
    f = lambda s: 1.0 - 2.0 * s + 0.5 * s**3  # noqa: E731
    assert np.allclose(L @ f(nodes), f(t), rtol=0, atol=1e-13)


@pytest.mark.validation
def test_corrected_grid_against_the_full_path_on_a_sphere_and_block(full_sphere_on_block):
    """The benchmark's steel sphere (R = 10) on a steel block (20 × 20 × 10,
    base clamped), frictionless, approach 0.03 mm of the sphere's base, a/h
    = 8.  Full path: both bodies meshed at h in the contact zone (5.6 s).
    Grid: two half-spaces plus each body's correction from its coarse mesh
    (fine size 0.5 mm ≈ 0.9a: 778 and 403 nodes), the sphere's curved face
    with its near field.  Measured: the half-spaces alone carry 4.1 % less
    force (the finite bodies are stiffer than two half-spaces to their
    supports); corrected, P is within −0.13 % of the full path, the
    correction's own estimate 9e-4 (the sphere's; the block's 2e-5).
    Asserted: the estimate within the applicability bound (LIMITS: 3e-3),
    the uncorrected force 3.5-5 % low (the test must see the finite
    bodies), the corrected one within the issue's 0.3 % and the pressure
    within 1.5 % of p0 (rms inside 0.9a; the full path's nodal values
    against the grid's cell values: the two discretizations' own
    difference at a/h = 8)."""
    a_over_h = 8.0
    a_guess = math.sqrt(10.0 * 0.03)
    P_full, r, p, h = full_sphere_on_block
    coarse = cases.SphereOnBlock(fine_radius=1.0, growth=0.45)
    block, sphere = cases.sphere_on_block(0.5, 0.03, setup=coarse).bodies
    nx = scipy.fft.next_fast_len(int(math.ceil(2.3 * a_over_h)))
    grid = Grid.centred(nx, nx, h, h)
    corrections = [BodyCorrection(block, 1, np.zeros(3), np.eye(3), grid),
                   BodyCorrection(sphere, 2, np.zeros(3), np.eye(3), grid,
                                  curvature=(0.1, 0.1))]
    assert max(c.estimate for c in corrections) < LIMITS["estimate"]
    Gs = coarse.youngs_modulus / (2.0 * (1.0 + coarse.poisson_ratio))
    pair = Compliance.pair(Gs, coarse.poisson_ratio, Gs, coarse.poisson_ratio)
    c = grid.centres
    rr = np.hypot(c[:, 0], c[:, 1])
    gap = 10.0 - np.sqrt(100.0 - rr**2)
    found = []
    for corr in ([], corrections):
        gi = GridInterface(PairOperator(grid, pair, corr), gap, 0.0)
        assert gi.solve_increment([math.nan] * 3, [0.0, 0.0, -0.03]).converged
        order = np.argsort(rr)
        p_at = np.interp(r, rr[order], gi.p[order, 2])
        inside = r < 0.9 * a_guess
        rms = float(np.sqrt(np.mean((p_at[inside] - p[inside]) ** 2)) / p.max())
        found.append((gi.force()[2] / P_full - 1.0, rms))
    (alone, _), (corrected, rms) = found
    assert -0.05 < alone < -0.035, alone
    assert abs(corrected) < 3e-3, corrected
    assert rms < 0.015, rms


def test_a_body_corrected_again_reuses_its_factorization(monkeypatch):
    """A sweep's points (or an assembly's grids) correct the same coarse
    body again: its mixed system is assembled and factored once
    (``coarse_factor``), and a correction made from the kept factorization is
    the fresh one's to the last bit (the same LU applied to the same data);
    another kind of supports is another factorization."""
    from bemcontact.bem import ElasticBody, Fixed
    from bemcontact.multiscale import coarse

    coarse.clear_coarse_factors()
    block = cases.sphere_on_block(0.5, 0.03, setup=cases.SphereOnBlock(
        fine_radius=1.0, growth=0.45)).bodies[0]
    calls = []
    original = type(block).mixed_system

    def counted(self, *args, **kwargs):
        calls.append(self.name)
        return original(self, *args, **kwargs)

    monkeypatch.setattr(type(block), "mixed_system", counted)
    grid = Grid.centred(16, 16, 0.07, 0.07)
    first = BodyCorrection(block, 1, np.zeros(3), np.eye(3), grid)
    again = BodyCorrection(block, 1, np.zeros(3), np.eye(3), grid)
    other = BodyCorrection(block, 1, np.zeros(3), np.eye(3), Grid.centred(20, 20, 0.05, 0.05))
    assert calls == ["block"]
    p = np.random.default_rng(0).normal(size=(grid.size, 3))
    np.testing.assert_array_equal(first.low_rank(p), again.low_rank(p))
    assert other.estimate < LIMITS["estimate"]
    sides = ElasticBody(block.mesh, block.material, {"zmin": Fixed(), "xmin": Fixed()},
                        name="block")
    BodyCorrection(sides, 1, np.zeros(3), np.eye(3), grid)
    assert calls == ["block", "block"]
    coarse.clear_coarse_factors()
