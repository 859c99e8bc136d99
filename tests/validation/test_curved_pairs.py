"""Curved on curved, other than two convex spheres (the spheres are in
test_frame_between.py): the default frame (``frame_on = "auto"``: both
surfaces curved, so between them) and the default projected relative
displacement, identical steel bodies (E = 210 GPa, nu = 0.3), pressed in 4
increments with Coulomb friction mu = 0.3 (bemcontact.validation.curved).

* Crossed cylinders: two half cylinders R = 10 mm, 20 mm long, axes along x
  and y, graded to h = 0.1 mm within 0.7 mm of the contact point (tri3),
  approach 0.03 mm.  Equal radii crossed at right angles: a circular Hertz
  contact with R_eff = R (a = 0.556 mm, a/h = 5.6).
* Sphere in a spherical seat: a hemisphere R1 = 10 mm in a dimple R2 = 12 mm
  of a 20 x 20 x 10 mm block (a conforming contact), approach 0.005 mm:
  Hertz with R_eff = R1 R2 / (R2 - R1) = 60 mm (a = 0.557 mm, a/R1 =
  0.056: the quadratic gap holds to (3/4)(a/R1)^2 = 0.2 %).

Tiers and why:
* Hertz for the computed force within the Hertz validation's tiers (3 %
  contact radius and peak, 5 % profile L2 on r < 0.9 a;
  test_hertz_mindlin.py).  Crossed cylinders: measured +1.4 / +0.04 / 3.0 %.
  The seat needs curved tri6 (the slow test: -0.14 / +0.25 / 1.5 %): with
  flat tri3 each surface's facets lie up to h^2/(8R) = 1.25e-4 mm inside it
  and the two meshes' facets do not match, a gap noise of 5 % of the
  conforming gap's variation a^2/(2 R_eff) = 2.6e-3 mm (12 times the
  share it has between two convex spheres), which the stiff contact turns
  into pressure noise of +-0.3 p0 at h = 0.1 (peak +32 %, profile 16 %;
  the fitted contact radius -0.05 %, asserted within 3 %).
* Whichever body is named first, the same numbers (1e-9 force, 1e-6
  shear: the frame and its integration do not depend on the order; measured
  equal to round-off).
* Frictional normal force = frictionless to 1e-4 for the crossed cylinders
  (measured 5.5e-5).  Seat: measured 2.7e-4 (tri6), asserted 4e-4, a
  regression bound (1e-4 is the bound for identical bodies; the seat's two
  surfaces are not).
* max |q| / p0 above 0.01 is the physics, not an error: the shear of two
  curved bodies that are not mirror images converges under refinement to
  a field of the pair's symmetry, first order in a/R (docs/validation.md,
  "What the shear between curved bodies is"; asserted below by its pattern
  and its a/R scaling).  Regression bounds about 15 % above the measured
  max: crossed cylinders 0.0139 at h = 0.1, asserted 0.016; seat (tri6)
  0.0297, asserted 0.034 (tri3: 0.0235).
"""

from __future__ import annotations

import numpy as np
import pytest

import bemcontact as bc
from bemcontact.validation import cases, curved
from bemcontact.validation.reference import contact as ref

pytestmark = pytest.mark.validation

H = 0.1
MU = 0.3
OPTIONS = bc.SolverOptions(load_steps=4)
SETUP = cases.SphereOnBlock()
SEAT_RADIUS = 12.0


def _shear(res: bc.ContactResult) -> float:
    fr = res.frame
    return float(np.linalg.norm(fr.tangential_traction, axis=1).max() / fr.pressure.max())


def _pair(build, **kw):
    """Frictionless and frictional solves of one condensation."""
    p = build(friction_coefficient=0.0, **kw)
    condensed = p.condense(OPTIONS)
    free = p.solve(OPTIONS, condensed=condensed)
    fric = build(friction_coefficient=MU, **kw).solve(OPTIONS, condensed=condensed)
    assert free.converged and fric.converged
    return free, fric


def _hertz(res, r_eff):
    return cases.hertz_errors(res.frame, ref.hertz(res.normal_force, r_eff, SETUP.contact_modulus))


# ---------------------------------------------------------------- crossed cylinders
def _cylinders(**kw):
    return curved.crossed_cylinders(H, **kw)


@pytest.fixture(scope="module")
def cylinders():
    return _pair(_cylinders)


def test_crossed_cylinders_hertz(cylinders):
    free, _ = cylinders
    e = _hertz(free, SETUP.radius)
    print(f"crossed cylinders: a {e.contact_radius:+.4f} p0 {e.peak_pressure:+.4f} "
          f"L2 {e.profile_l2:.4f}")
    assert abs(e.contact_radius) <= 0.03 and abs(e.peak_pressure) <= 0.03, e
    assert e.profile_l2 <= 0.05, e


def test_crossed_cylinders_friction(cylinders):
    free, fric = cylinders
    q = _shear(fric)
    dn = abs(fric.normal_force / free.normal_force - 1)
    print(f"crossed cylinders: max |q| {q:.4f} p0, dN {dn:.1e}")
    assert fric.frame.counts()["stick"] > 50  # the friction is engaged
    assert dn <= 1e-4, f"normal force with friction differs by {dn:.2e}"
    # regression bound (measured 0.0139): above 0.01 p0, the curvature
    # coupling (next test), not an error
    assert q <= 0.016, f"max |q| = {q:.4f} p0 between identical crossed cylinders"


def test_crossed_cylinders_shear_is_the_curvature_coupling(cylinders):
    """The shear between the crossed cylinders is the first-order effect of
    the two bodies' different curvatures, not discretization error:
    * its pattern is the saddle field (x, -y) that their half-turn symmetry
      allows and their curvatures (1/R across one axis, across the other
      for the other body) call for: that pattern, with an amplitude fitted
      per ring of radius, carries at least 80 % of |q|^2 (measured 88 %; a
      shear from node-to-node discretization noise has about 0 %);
    * at the same a/h (5.6) with R doubled (a/R 0.056 -> 0.028, approach
      halved so a stays 0.56 mm) its root mean square falls by 1.4-2.2
      (measured 1.67; at h = 0.05, 1.80): first order in a/R (second order
      would give 4, an error of the discretization at fixed a/h 1);
    * (docs/validation.md, not asserted here: 27-40 s each) at fixed a/R
      it converges under refinement, rms 0.0067 / 0.0072 / 0.0074 p0 at
      a/h = 5.6 / 8.1 / 11.3.
    The largest |q| is one node's value near the stick-slip front and moves
    with the mesh (R = 20: 0.0181 here, 0.0106 at approach 0.0155), so the
    pattern and the rms are asserted, not it."""
    _, fric = cylinders
    share, rms = curved.shear_pattern(fric.frame, "saddle")
    wide = cases.SphereOnBlock(radius=2 * SETUP.radius)
    half = _cylinders(friction_coefficient=MU, setup=wide, approach=0.03 / 2).solve(OPTIONS)
    share2, rms2 = curved.shear_pattern(half.frame, "saddle")
    print(f"crossed cylinders: saddle share {share:.3f} rms {rms:.4f} p0; R = 20: share "
          f"{share2:.3f} rms {rms2:.4f} p0, rms ratio {rms / rms2:.2f}")
    assert half.converged and half.frame.counts()["stick"] > 50
    assert share >= 0.8, f"only {share:.1%} of the shear is the saddle pattern"
    assert 1.4 <= rms / rms2 <= 2.2, f"rms shear {rms:.4f} -> {rms2:.4f} p0 when a/R halves"


def test_crossed_cylinders_body_order(cylinders):
    _, fric = cylinders
    swapped = _cylinders(friction_coefficient=MU, swap=True).solve(OPTIONS)
    assert swapped.names == ("upper", "lower")
    assert swapped.normal_force == pytest.approx(fric.normal_force, rel=1e-9)
    assert _shear(swapped) == pytest.approx(_shear(fric), rel=1e-6, abs=1e-9)


# -------------------------------------------------------------------- seat
def _seat(**kw):
    return curved.sphere_in_seat(H, seat_radius=SEAT_RADIUS, **kw)


R_SEAT = curved.seat_effective_radius(SETUP.radius, SEAT_RADIUS)


def test_seat_flat_facets():
    """tri3: the body order does not matter and the fitted contact radius
    is Hertz's (measured -0.05 %); peak and profile are not (see the
    module docstring), so they are asserted on tri6 below."""
    p = _seat(friction_coefficient=MU)
    res = p.solve(OPTIONS)
    swapped = _seat(friction_coefficient=MU, swap=True).solve(OPTIONS)
    assert res.converged and swapped.names == ("upper", "lower")
    assert swapped.normal_force == pytest.approx(res.normal_force, rel=1e-9)
    assert _shear(swapped) == pytest.approx(_shear(res), rel=1e-6, abs=1e-9)
    e = _hertz(res, R_SEAT)
    print(f"seat tri3: a {e.contact_radius:+.4f} p0 {e.peak_pressure:+.4f} L2 {e.profile_l2:.4f}, "
          f"max |q| {_shear(res):.4f}")
    assert abs(e.contact_radius) <= 0.03, e


@pytest.mark.slow
def test_seat_curved_facets():
    """tri6 (h = 0.1 mm, grading 0.6 per mm up to 3 mm; 1260 + 994
    elements; about 100 s): Hertz with R_eff = 60 mm within the tiers
    (measured -0.14 / +0.25 / 1.5 %); shear and normal-force change as
    regression bounds (module docstring)."""
    setup = cases.SphereOnBlock(growth=0.6, coarse_size=3.0)
    free, fric = _pair(_seat, order=2, setup=setup)
    e = _hertz(free, R_SEAT)
    q = _shear(fric)
    dn = abs(fric.normal_force / free.normal_force - 1)
    print(f"seat tri6: a {e.contact_radius:+.4f} p0 {e.peak_pressure:+.4f} L2 {e.profile_l2:.4f}, "
          f"max |q| {q:.4f} p0, dN {dn:.1e}")
    assert abs(e.contact_radius) <= 0.03 and abs(e.peak_pressure) <= 0.03, e
    assert e.profile_l2 <= 0.05, e
    assert fric.frame.counts()["stick"] > 50
    assert dn <= 4e-4, f"normal force with friction differs by {dn:.2e}"
    assert q <= 0.034, f"max |q| = {q:.4f} p0 in the seat"
