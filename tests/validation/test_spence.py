"""Spence's problem: a hemisphere 10x stiffer than the block it is pressed
on (sphere E = 2.1e6 MPa, nu = 0.3; block E = 2.1e5 MPa, nu = 0.4; Dundurs'
beta = 0.122 with the block as body 1), friction mu = beta/1.7 = 0.072, the
sphere's base pushed down by 0.03 mm in 10 equal increments (a = 0.57 mm;
mesh h = 0.07 mm, a/h = 8; a cap of height 2.5 mm on a 10 x 10 x 5 mm block,
graded as sphere_on_block).  Nothing tangential is applied: the shear comes
from the mismatch of the surfaces' radial displacements under the pressure
alone.  Reference: the self-similar solution in the uncoupled approximation
(reference/contact.py: spence_stick_radius, spence_traction; Spence 1975),
for the computed force (Hertz a and p0 from P).

Tiers and why:
* stick radius within one element of the reference (|c - c_ref| <= h, the
  boundary of a nodal stick zone is located to about an element; measured
  c/a 0.632 against 0.612, +0.012 mm).
* radial traction L2 (r < 0.9 a) <= 0.15 (measured 0.116): the history of
  the stuck points is resolved by 10 load increments (5 increments: 0.24);
  a regression bound, not a convergence claim.
* direction: the slipping block nodes carry mu p pointing away from the axis
  (the block, with the larger (1 - 2 nu)/G, is drawn inward by the
  pressure more than the sphere; friction resists) to 1 %, no node carries
  inward shear; the sphere carries the opposite.
* pressure: Hertz within the Hertz tiers (fitted a 3 %, profile L2 5 %;
  measured -0.2 % and 1.8 %): with beta mu = 0.009 the shear's effect on
  the pressure, which the reference neglects, is small.  With beta = 0.43,
  mu = 0.25 (docs/validation.md) it is not: the peak pressure rises ~19 %.
"""

from __future__ import annotations

import numpy as np
import pytest

from bemcontact.validation import cases
from bemcontact.validation import dissimilar as ds
from bemcontact import SolverOptions
from bemcontact.contact.law import SLIP
from bemcontact.validation.reference import contact as ref

pytestmark = pytest.mark.validation

H = 0.07
APPROACH = 0.03
INCREMENTS = 10
GEOMETRY = cases.SphereOnBlock(block_half_width=5.0, block_depth=5.0, coarse_size=2.0, growth=0.4)
SETUP = ds.DissimilarSphereOnBlock(block_poisson_ratio=0.4, geometry=GEOMETRY)
MU = SETUP.beta / 1.7


@pytest.fixture(scope="module")
def both():
    """The default solve and the one with closing = "first_touch", on one
    condensation."""
    p = ds.dissimilar_sphere_on_block(H, APPROACH, MU, setup=SETUP, cap_height=2.5)
    steps = ds.spence_steps(APPROACH, INCREMENTS)
    cond = p.condense(steps=steps)
    out = []
    for closing in ("frictionless", "first_touch"):
        res = p.solve(SolverOptions(closing=closing), steps=steps, condensed=cond)
        assert res.converged
        out.append((res, ref.hertz(res.normal_force, GEOMETRY.radius, SETUP.contact_modulus)))
    return out


@pytest.fixture(scope="module")
def solved(both):
    return both[0]


def _radial_l2(res, h) -> float:
    """Weighted L2 error (r < 0.9a) of the radial shear against Spence's."""
    fr = res.frame
    r, qr = ds.radial_shear(fr)
    inner = r < 0.9 * h.contact_radius
    exact = ref.spence_traction(r[inner], h.contact_radius, h.peak_pressure, SETUP.beta, MU)
    return cases.weighted_l2(qr[inner], exact, fr.weights[inner])


def test_first_touch_gives_the_last_ring_its_shear(both):
    """closing = "first_touch" (SolverOptions): the nodes closing in an
    increment take friction from their estimated first touch, so the ring
    that closes in the last increment carries mu p outward too (1 %, as the
    others: measured 0.995-1.0) and the radial traction's L2 error falls to
    4 % (measured 2.2 %, against 11.6 % by default: the closing ring was most
    of it); the stick radius stays within one element (measured c/a
    0.629)."""
    res, h = both[1]
    fr = res.frame
    r, qr = ds.radial_shear(fr)
    e = _radial_l2(res, h)
    print(f"first_touch: radial traction L2 (r < 0.9a) = {e:.4f}")
    assert e <= 0.04
    ring = (fr.state == SLIP) & (r > np.sqrt((INCREMENTS - 1) / INCREMENTS) * h.contact_radius)
    assert ring.sum() > 10
    np.testing.assert_allclose(qr[ring], MU * fr.pressure[ring], rtol=1e-2)
    c = cases.stick_radius(fr)
    assert abs(c - ref.spence_stick_radius(h.contact_radius, SETUP.beta, MU)) <= H


def test_setup_numbers():
    assert SETUP.beta == pytest.approx(0.12245, abs=1e-5)
    assert ref.spence_stick_radius(1.0, SETUP.beta, MU) == pytest.approx(0.6120, abs=1e-4)


def test_stick_radius(solved):
    res, h = solved
    c = cases.stick_radius(res.frame)
    c_ref = ref.spence_stick_radius(h.contact_radius, SETUP.beta, MU)
    print(f"c/a = {c / h.contact_radius:.4f}, reference {c_ref / h.contact_radius:.4f}")
    assert abs(c - c_ref) <= H, (c, c_ref)
    assert res.frame.counts()["stick"] > 30


def test_radial_traction_profile(solved):
    res, h = solved
    e = _radial_l2(res, h)
    print(f"radial traction L2 (r < 0.9a) = {e:.4f}")
    assert e <= 0.15


def test_shear_direction(solved):
    """Outward on the block (beta > 0 with the block as body 1): mu p at the
    slipping nodes that were closed before the last increment (r <
    sqrt(9/10) a; the ring closing in the last increment carries no shear,
    see docs/validation.md), to 1 % (measured 0.994-0.999: the direction's
    tilt); nowhere inward; the hoop component below 0.1 mu p0 (measured
    0.066, in the stick zone); the sphere gets the opposite."""
    res, h = solved
    fr = res.frame
    r, qr = ds.radial_shear(fr)
    t = np.linalg.norm(fr.tangential_traction, axis=1)
    a, q0 = h.contact_radius, MU * h.peak_pressure
    slip = (fr.state == SLIP) & (r < np.sqrt((INCREMENTS - 1) / INCREMENTS) * a)
    assert slip.sum() > 20
    np.testing.assert_allclose(qr[slip], MU * fr.pressure[slip], rtol=1e-2)
    assert qr.min() >= -1e-3 * q0
    hoop = np.sqrt(np.maximum(t**2 - qr**2, 0.0))
    print(f"max hoop component {hoop.max() / q0:.4f} mu p0")
    assert hoop.max() <= 0.1 * q0
    # body 2 (the sphere) receives the frame's traction: pointing inward
    d = fr.points[:, :2]
    assert np.einsum("ij,ij->", fr.tangential_traction[slip, :2], d[slip]) < 0


def test_pressure_stays_hertzian(solved):
    res, h = solved
    e = cases.hertz_errors(res.frame, h)
    print(e)
    assert abs(e.contact_radius) <= 0.03 and e.profile_l2 <= 0.05, e
