"""Hertz, Cattaneo–Mindlin and Mindlin–Deresiewicz: a steel hemisphere
(R = 10 mm) pressed on a steel block (20 x 20 x 10 mm) by an approach of
0.03 mm (a ≈ 0.555 mm, a/R = a/L ≈ 0.055), then loaded tangentially through
its base by a force Q at constant approach (docs/validation.md).

Meshes graded to element size h within 0.7 mm of the contact point; the
analytic comparisons use the *computed* normal force P (Hertz a and p0 from
P).  Identical materials: the normal and tangential problems decouple, as
Cattaneo–Mindlin assume.  The tangential displacement of "distant points" of
Cattaneo–Mindlin is a half-space notion: the platen's translation U also
holds the linear elastic compliance of the finite bodies, measured from a
small all-stick step (Q = 0.02 mu P) and replaced by the contact's own
initial compliance S / (8 a) (Johnson §7.2)."""

from __future__ import annotations

import numpy as np
import pytest

import bemcontact as bc
from bemcontact import cases
from bemcontact.reference import contact as ref

pytestmark = pytest.mark.validation

SETUP = cases.SphereOnBlock()
SIZES = (0.1, 0.07, 0.05)
MU = 0.3


def _hertz(P):
    return ref.hertz(P, SETUP.radius, SETUP.contact_modulus)


@pytest.fixture(scope="module")
def frictionless():
    out = []
    for h in SIZES:
        res = cases.sphere_on_block(h).solve()
        out.append((h, res, cases.hertz_errors(res.frame, _hertz(res.normal_force))))
    return out


def test_hertz_invariants(frictionless):
    """Tier (a)/(b): converged, interface forces balance the frame force, no
    tension, no penetration where pressed, and nothing tangential."""
    for h, res, _ in frictionless:
        assert res.converged
        fr = res.frame
        F1 = res.bodies[0].weights[res.interfaces[0].nodes] @ res.interfaces[0].traction
        assert np.allclose(F1, -res.contact_force, atol=1e-8 * res.normal_force)
        assert fr.pressure.min() >= -1e-9 * fr.pressure.max()
        closed = fr.state > 0
        assert np.abs(fr.gap[closed]).max() <= 1e-9 * SETUP.radius
        assert np.abs(fr.tangential_traction).max() == 0.0


def test_hertz_frictionless_matches_and_converges(frictionless):
    """Finest mesh (h = 0.05 mm, 22 elements across the contact diameter):
    contact radius and peak pressure within 3 % and the profile within 5 %
    (L2, r < 0.9 a) of Hertz for the computed force, the issue's tolerances;
    measured 0.7 %, 0.7 %, 2.3 %.  All three errors fall on every refinement,
    at fitted rates >= 1 (the profile's measured rate is printed)."""
    hs = [h for h, _, _ in frictionless]
    e = [x for _, _, x in frictionless]
    fin = e[-1]
    assert abs(fin.contact_radius) <= 0.03
    assert abs(fin.peak_pressure) <= 0.03
    assert fin.profile_l2 <= 0.05
    for name in ("contact_radius", "peak_pressure", "profile_l2"):
        err = [abs(getattr(x, name)) for x in e]
        assert all(b < a for a, b in zip(err, err[1:])), (name, err)
        rate = cases.fitted_rate(hs, err)
        print(f"{name}: errors {['%.4f' % v for v in err]} fitted rate {rate:.2f}")
        assert rate >= 1.0, (name, rate)
