"""bemcontact.validation.reference.contact: the classical analytic contact solutions.

Each formula is checked against an independent property (an integral, a
derivative, a limit or a published example) rather than re-typed: resultants
by adaptive quadrature (1e-8 relative, far above quad's error estimate),
derivatives by central differences (1e-6, FD truncation), the published
Hertz example to its 4 printed digits."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad

from bemcontact import ConfigError
from bemcontact.validation.reference import (
    boussinesq_punch_force,
    boussinesq_punch_pressure,
    cattaneo_mindlin_displacement,
    cattaneo_mindlin_stick_radius,
    cattaneo_mindlin_traction,
    effective_modulus,
    fretting_loop_energy,
    hertz,
    hertz_force,
    mindlin_deresiewicz_unloading,
    tangential_compliance_factor,
)

E, NU = 210e3, 0.3  # steel, MPa
G = E / (2 * (1 + NU))
ES = effective_modulus(E, NU, E, NU)
S = tangential_compliance_factor(G, NU, G, NU)


def disc_integral(f, a):
    return 2 * math.pi * quad(lambda r: f(r) * r, 0, a, limit=200, epsabs=0, epsrel=1e-12)[0]


def test_effective_modulus():
    assert ES == pytest.approx(E / (2 * (1 - NU**2)), rel=1e-15)
    assert effective_modulus(E, NU, math.inf, 0.0) == pytest.approx(E / (1 - NU**2), rel=1e-15)


def test_hertz_published_example():
    """validation.md: steel sphere R = 10 mm on steel flat, P = 100 N:
    a = 0.1866 mm, p0 = 1371 MPa (4 digits printed)."""
    h = hertz(100.0, 10.0, ES)
    assert h.contact_radius == pytest.approx(0.1866, abs=5e-5)
    assert h.peak_pressure == pytest.approx(1371, abs=0.5)
    assert h.peak_pressure == pytest.approx(1.5 * h.mean_pressure, rel=1e-15)


def test_hertz_pressure_resultant_and_force_approach_law():
    h = hertz(100.0, 10.0, ES)
    assert disc_integral(h.pressure, h.contact_radius) == pytest.approx(100.0, rel=1e-8)
    assert h.pressure(h.contact_radius * 1.01) == 0.0
    assert hertz_force(h.approach, 10.0, ES) == pytest.approx(100.0, rel=1e-12)


def test_cattaneo_mindlin_traction():
    h = hertz(100.0, 10.0, ES)
    mu, Q = 0.3, 15.0  # Q / (mu P) = 0.5
    c = cattaneo_mindlin_stick_radius(h.contact_radius, Q, mu, 100.0)
    assert c == pytest.approx(h.contact_radius * 0.5 ** (1 / 3), rel=1e-15)
    q = lambda r: cattaneo_mindlin_traction(r, h, Q, mu)  # noqa: E731
    # resultant equals Q; full slip (q = mu p) in the annulus c < r < a; below mu p inside
    assert disc_integral(q, h.contact_radius) == pytest.approx(Q, rel=1e-8)
    r_slip = np.linspace(c * 1.001, h.contact_radius, 7)
    np.testing.assert_allclose(q(r_slip), mu * h.pressure(r_slip), rtol=1e-14)
    r_stick = np.linspace(0, c * 0.999, 7)
    assert np.all(q(r_stick) < mu * h.pressure(r_stick))
    # Q -> 0: c -> a
    assert cattaneo_mindlin_stick_radius(h.contact_radius, 0.0, mu, 100.0) == h.contact_radius


def test_mindlin_displacement_initial_compliance_and_branches():
    """Initial slope dδ/dQ = S / (8a) (Mindlin's elastic compliance); the
    unloading branch starts on the loading curve with that same slope and
    ends at the mirror point."""
    h = hertz(100.0, 10.0, ES)
    a, mu, P = h.contact_radius, 0.3, 100.0
    eps = 1e-4
    slope0 = cattaneo_mindlin_displacement(eps, mu, P, a, S) / eps
    assert slope0 == pytest.approx(S / (8 * a), rel=1e-5)
    Qm = 20.0
    dm = cattaneo_mindlin_displacement(Qm, mu, P, a, S)
    assert mindlin_deresiewicz_unloading(Qm, Qm, mu, P, a, S) == pytest.approx(dm, rel=1e-14)
    assert mindlin_deresiewicz_unloading(-Qm, Qm, mu, P, a, S) == pytest.approx(-dm, rel=1e-14)
    h_ = 1e-3
    d1 = mindlin_deresiewicz_unloading(Qm - h_, Qm, mu, P, a, S)
    assert (dm - d1) / h_ == pytest.approx(S / (8 * a), rel=1e-4)
    # unloading lags loading: above the reloading branch everywhere inside
    Q = np.linspace(-Qm * 0.99, Qm * 0.99, 11)
    up = -mindlin_deresiewicz_unloading(-Q, Qm, mu, P, a, S)
    down = mindlin_deresiewicz_unloading(Q, Qm, mu, P, a, S)
    assert np.all(down > up)


@pytest.mark.parametrize("x", [0.05, 0.5, 0.9])
def test_fretting_loop_energy_is_the_loop_area(x):
    h = hertz(100.0, 10.0, ES)
    a, mu, P = h.contact_radius, 0.3, 100.0
    Qm = x * mu * P
    gap = lambda Q: (  # noqa: E731
        mindlin_deresiewicz_unloading(Q, Qm, mu, P, a, S)
        + mindlin_deresiewicz_unloading(-Q, Qm, mu, P, a, S)
    )
    area = quad(gap, -Qm, Qm, epsabs=0, epsrel=1e-12)[0]
    assert fretting_loop_energy(Qm, mu, P, a, S) == pytest.approx(area, rel=1e-8)


def test_fretting_loop_energy_small_amplitude_limit():
    """W -> S Q*^3 / (36 a mu P) as Q*/(mu P) -> 0 (relative correction O(x*))."""
    h = hertz(100.0, 10.0, ES)
    a, mu, P = h.contact_radius, 0.3, 100.0
    for x in (1e-2, 1e-3):
        Qm = x * mu * P
        ratio = fretting_loop_energy(Qm, mu, P, a, S) / (S * Qm**3 / (36 * a * mu * P))
        assert ratio == pytest.approx(1.0, abs=2 * x)


def test_boussinesq_punch():
    a, delta = 1.5, 1e-3
    F = boussinesq_punch_force(a, delta, ES)
    assert F == pytest.approx(2 * a * ES * delta, rel=1e-15)
    p = lambda r: boussinesq_punch_pressure(np.array([r]), a, F)[0]  # noqa: E731
    assert disc_integral(p, a) == pytest.approx(F, rel=1e-8)
    assert boussinesq_punch_pressure(np.array([0.0]), a, F)[0] == pytest.approx(
        F / (2 * math.pi * a * a), rel=1e-15
    )  # centre: half the mean pressure
    assert boussinesq_punch_pressure(np.array([a * 1.1]), a, F)[0] == 0.0


@pytest.mark.parametrize(
    "call, match",
    [
        (lambda: hertz(-1.0, 10.0, ES), "normal_force must be a finite number > 0"),
        (lambda: hertz(1.0, math.nan, ES), "radius must be a finite number > 0"),
        (lambda: cattaneo_mindlin_stick_radius(1.0, 40.0, 0.3, 100.0), "0 <= Q < mu P"),
        (lambda: fretting_loop_energy(1.0, 0.0, 100.0, 1.0, 1.0), "friction_coefficient"),
        (lambda: mindlin_deresiewicz_unloading(5.0, 1.0, 0.3, 100.0, 1.0, 1.0), "-Q_max <= Q"),
    ],
)
def test_bad_arguments_are_config_errors(call, match):
    with pytest.raises(ConfigError, match=match):
        call()
