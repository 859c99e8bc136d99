"""Spence's problem in bemcontact.validation.reference.contact: dissimilar
elastic bodies pressed together by a growing normal load with friction.

The stick-zone equation and the traction are derived in the uncoupled
approximation (docstring of ``spence_stick_radius``); no printed table of
Spence (1975) or Johnson (1985) was at hand to compare digits with, so each
piece is checked against an independent property instead:

* Dundurs' beta against its limits (1/2 for a rigid body on nu = 0, 0 for
  identical bodies, antisymmetric in the order of the bodies).
* The stick-zone increment against the half-space itself: the radial surface
  displacement it produces, computed from Cerruti's point-force solution
  integrated over rings (not the Hankel/Abel machinery of the derivation),
  equals the stick condition beta dU[p]/da on r < c (quadrature, 1e-7), and
  in the slip zone the increment is mu dp/da (1e-10).
* The traction: mu p in the slip annulus, continuous at c, below mu p in the
  stick zone, and its growth with a at fixed r equal to that increment
  (central differences, 1e-5: the self-similar history is the sum of the
  increments).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.special import ellipkm1

from bemcontact import ConfigError
from bemcontact.validation.reference import contact as ref


def test_dundurs_beta_limits():
    assert ref.dundurs_beta(210e3, 0.0, math.inf, 0.3) == pytest.approx(0.5, rel=1e-15)
    assert ref.dundurs_beta(70e3, 0.3, 70e3, 0.3) == 0.0
    b = ref.dundurs_beta(70e3, 0.1, 700e3, 0.3)
    assert ref.dundurs_beta(700e3, 0.3, 70e3, 0.1) == pytest.approx(-b, rel=1e-15)
    # by hand: G1 = 70e3/2.2, G2 = 700e3/2.6
    G1, G2 = 70e3 / 2.2, 700e3 / 2.6
    assert b == pytest.approx((0.8 / G1 - 0.4 / G2) / (2 * (0.9 / G1 + 0.7 / G2)), rel=1e-14)
    # incompressible on rigid: no coupling
    assert ref.dundurs_beta(1.0, 0.5, math.inf, 0.2) == 0.0
    with pytest.raises(ConfigError, match="both bodies rigid"):
        ref.dundurs_beta(math.inf, 0.3, math.inf, 0.3)


@pytest.mark.parametrize("k", [0.05, 0.3, 0.6, 0.775, 0.9, 0.99])
def test_stick_radius_solves_its_equation(k):
    x = k * ellipkm1(k * k) / math.atanh(k)  # beta/mu for this k
    mu = 0.5 / x * 0.9
    beta = 0.9 * 0.5
    c = ref.spence_stick_radius(2.0, beta, mu)
    assert c / 2.0 == pytest.approx(k, rel=1e-12)
    assert ref.spence_stick_radius(2.0, -beta, mu) == c  # only |beta| matters


def test_stick_radius_limits():
    a = 1.0
    assert ref.spence_stick_radius(a, 0.0, 0.3) == 1.0  # nothing drives slip
    assert ref.spence_stick_radius(a, 0.3, 0.0) == 0.0  # frictionless: all slip
    # beta/mu -> inf: c/a ~ 4 exp(-beta/mu) (K(k') ~ ln(4/k), artanh k ~ k)
    assert ref.spence_stick_radius(a, 0.5, 0.5 / 30) == pytest.approx(4 * math.exp(-30), rel=1e-6)
    # monotone: more friction, larger stick zone
    cs = [ref.spence_stick_radius(a, 0.4, m) for m in (0.1, 0.2, 0.3, 0.5, 1.0, 3.0)]
    assert all(x < y for x, y in zip(cs, cs[1:])) and cs[-1] < 1.0
    with pytest.raises(ConfigError, match="beta"):
        ref.spence_stick_radius(a, 0.6, 0.3)


BETA, MU = 0.4, 0.3


def _cerruti_ring(r, s, nu=0.25):
    """Radial displacement at radius r of a half-space with (1 - nu)/G = 1
    loaded by a unit radial line traction on the circle of radius s
    (Cerruti: u_i = [(1 - nu) d_ij / rho + nu x_i x_j / rho^3] F_j / (2 pi G))."""
    G = 1 - nu

    def f(th):
        c, sn = np.cos(th), np.sin(th)
        dx, dy = r - s * c, -s * sn
        rho = np.hypot(dx, dy)
        return ((1 - nu) * c / rho + nu * (r * c - s) * dx / rho**3) / (2 * np.pi * G)

    return 2 * quad(f, 0, np.pi, limit=400, epsabs=1e-12)[0]


@pytest.mark.parametrize("r", [0.3, 0.7])
def test_stick_increment_satisfies_the_stick_condition(r):
    """a = 1, p0 = C a with C = 1: the stuck points' increment dq/da must move
    body 1 radially by beta dU[p]/da = beta (a - sqrt(a^2 - r^2)) / r (so the
    relative radial displacement K (U[q] - beta U[p]) does not change)."""
    k = ref.spence_stick_radius(1.0, BETA, MU)
    assert r < k

    def psi(s):
        return MU * ref._spence_increment(s, k, BETA / MU)

    u = quad(lambda s: psi(s) * s * _cerruti_ring(r, s), 0, 1, points=[r, k], limit=400,
             epsabs=1e-10, epsrel=1e-9)[0]
    assert u == pytest.approx(BETA * (1 - math.sqrt(1 - r * r)) / r, rel=1e-7)
    # slip zone: mu dp/da
    for s in (k + 1e-9, 0.9, 0.999):
        assert psi(s) == pytest.approx(MU / math.sqrt(1 - s * s), rel=1e-10)
    assert psi(k - 1e-9) == pytest.approx(MU / math.sqrt(1 - k * k), rel=1e-3)  # continuous


def test_traction_is_the_history_of_the_increments():
    a, C = 1.3, 2.0  # p0 = C a grows with a (Hertz)
    k = ref.spence_stick_radius(1.0, BETA, MU)
    r = a * np.array([0.02, 0.2, 0.5, 0.7, 0.95 * k, 0.9, 0.99, 1.05])
    q = ref.spence_traction(r, a, C * a, BETA, MU)
    p = C * a * np.sqrt(np.clip(1 - (r / a) ** 2, 0, None))
    slip = r / a > k
    np.testing.assert_allclose(q[slip], MU * p[slip], rtol=1e-14)
    assert np.all(q[~slip] < MU * p[~slip]) and np.all(q[~slip] > 0)
    c = k * a
    qc = ref.spence_traction([c * (1 - 1e-9), c * (1 + 1e-9)], a, C * a, BETA, MU)
    assert qc[0] == pytest.approx(qc[1], rel=1e-6)
    # d q / d a at fixed r = C psi(r/a) (psi in units mu)
    h = 1e-4 * a
    dq = (ref.spence_traction(r, a + h, C * (a + h), BETA, MU)
          - ref.spence_traction(r, a - h, C * (a - h), BETA, MU)) / (2 * h)
    for ri, d in zip(r[:5], dq[:5]):
        assert d == pytest.approx(C * MU * ref._spence_increment(ri / a, k, BETA / MU), rel=1e-5)
    # sign: body 1 pulled outward when beta > 0, inward when beta < 0
    np.testing.assert_array_equal(ref.spence_traction(r, a, C * a, -BETA, MU), -q)
    assert not np.any(ref.spence_traction(r, a, C * a, 0.0, MU))
