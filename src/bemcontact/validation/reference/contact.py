"""Classical analytic contact solutions (half-spaces, small strain).

Sources (formulas only): K. L. Johnson, *Contact Mechanics*, Cambridge 1985,
§3.4 (flat punch), §4.2 (Hertz), §7.2 (Cattaneo–Mindlin), §7.4
(Mindlin–Deresiewicz unloading and the fretting loop); design notes
``validation.md``.  Units are any consistent set (docs/theory.md); pressures
and tractions > 0 as in the package conventions (pressure compressive).

Notation: P normal force, Q tangential force (0 <= |Q| < mu P), R effective
radius 1/R = 1/R1 + 1/R2, E* = 1 / ((1 - nu1^2)/E1 + (1 - nu2^2)/E2),
a contact radius, p0 peak pressure, G shear modulus.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...errors import ConfigError


def _positive(name: str, value: float) -> float:
    v = float(value)
    if not (math.isfinite(v) and v > 0):
        raise ConfigError(f"{name} must be a finite number > 0, got {value!r}")
    return v


def _ratio(Q: float, mu: float, P: float) -> float:
    """Q / (mu P), checked to lie in [0, 1)."""
    x = float(Q) / (_positive("friction_coefficient", mu) * _positive("normal_force", P))
    if not (0.0 <= x < 1.0):
        raise ConfigError(
            f"tangential force must satisfy 0 <= Q < mu P (partial slip), got Q / (mu P) = {x!r}"
        )
    return x


def effective_modulus(E1: float, nu1: float, E2: float, nu2: float) -> float:
    """Contact modulus E* = 1 / ((1 - nu1^2)/E1 + (1 - nu2^2)/E2).  Pass
    E2 = math.inf for a rigid second body."""
    c2 = 0.0 if math.isinf(E2) else (1 - nu2**2) / _positive("E2", E2)
    return 1.0 / ((1 - nu1**2) / _positive("E1", E1) + c2)


def tangential_compliance_factor(G1: float, nu1: float, G2: float, nu2: float) -> float:
    """S = (2 - nu1)/G1 + (2 - nu2)/G2, the factor of the Mindlin
    tangential compliance for two bodies (Johnson §7.2)."""
    return (2 - nu1) / _positive("G1", G1) + (2 - nu2) / _positive("G2", G2)


@dataclass(frozen=True)
class Hertz:
    """Hertz solution for a sphere (effective radius R) pressed by P.

    contact_radius a = (3 P R / (4 E*))^(1/3); peak_pressure p0 = 3 P / (2 pi a^2);
    mean_pressure P / (pi a^2); approach delta = a^2 / R (of distant points
    of two half-spaces).
    """

    normal_force: float
    radius: float
    contact_modulus: float
    contact_radius: float
    peak_pressure: float
    mean_pressure: float
    approach: float

    def pressure(self, r) -> np.ndarray:
        """p(r) = p0 sqrt(1 - r^2 / a^2) for r < a, 0 outside."""
        r = np.asarray(r, dtype=float)
        s = 1.0 - (r / self.contact_radius) ** 2
        return self.peak_pressure * np.sqrt(np.clip(s, 0.0, None))


def hertz(normal_force: float, radius: float, contact_modulus: float) -> Hertz:
    """Hertz contact of a sphere of radius R on a flat (or two spheres with
    effective radius R) under normal force P."""
    P = _positive("normal_force", normal_force)
    R = _positive("radius", radius)
    Es = _positive("contact_modulus", contact_modulus)
    a = (3.0 * P * R / (4.0 * Es)) ** (1.0 / 3.0)
    return Hertz(P, R, Es, a, 3.0 * P / (2.0 * math.pi * a * a), P / (math.pi * a * a), a * a / R)


def hertz_force(approach: float, radius: float, contact_modulus: float) -> float:
    """P(delta) = (4/3) E* R^(1/2) delta^(3/2) (displacement control)."""
    d = _positive("approach", approach)
    return 4.0 / 3.0 * _positive("contact_modulus", contact_modulus) * math.sqrt(
        _positive("radius", radius)
    ) * d**1.5


def cattaneo_mindlin_stick_radius(contact_radius: float, Q: float, mu: float, P: float) -> float:
    """c = a (1 - Q / (mu P))^(1/3)."""
    return _positive("contact_radius", contact_radius) * (1.0 - _ratio(Q, mu, P)) ** (1.0 / 3.0)


def cattaneo_mindlin_traction(r, h: Hertz, Q: float, mu: float) -> np.ndarray:
    """Magnitude of the tangential traction q(r) (along Q):
    mu p0 sqrt(1 - r^2/a^2) - (c/a) mu p0 sqrt(1 - r^2/c^2) (second term for
    r < c only), the Hertz contact ``h`` under P = h.normal_force."""
    c = cattaneo_mindlin_stick_radius(h.contact_radius, Q, mu, h.normal_force)
    r = np.asarray(r, dtype=float)
    q = mu * h.pressure(r)
    if c > 0:
        q = q - (c / h.contact_radius) * mu * h.peak_pressure * np.sqrt(
            np.clip(1.0 - (r / c) ** 2, 0.0, None)
        )
    return q


def cattaneo_mindlin_displacement(Q: float, mu: float, P: float, contact_radius: float,
                                  S: float) -> float:
    """Tangential approach of distant points under monotonic loading 0 -> Q:
    delta_t = (3 mu P / (16 a)) S [1 - (1 - Q/(mu P))^(2/3)], S from
    :func:`tangential_compliance_factor`."""
    x = _ratio(Q, mu, P)
    K = 3.0 * mu * P / (16.0 * _positive("contact_radius", contact_radius)) * _positive("S", S)
    return K * (1.0 - (1.0 - x) ** (2.0 / 3.0))


def mindlin_deresiewicz_unloading(Q, Q_max: float, mu: float, P: float, contact_radius: float,
                                  S: float) -> np.ndarray:
    """Tangential approach on the unloading branch Q_max -> Q >= -Q_max
    (Mindlin–Deresiewicz, Johnson §7.4): with K = 3 mu P S / (16 a),
    x = Q/(mu P), x* = Q_max/(mu P):

        delta = K [2 (1 - (x* - x)/2)^(2/3) - (1 - x*)^(2/3) - 1].

    It starts on the loading curve at Q_max and ends at -delta(Q_max).  The
    reloading branch -Q_max -> Q is -(unloading at -Q)."""
    xs = _ratio(Q_max, mu, P)
    x = np.asarray(Q, dtype=float) / (mu * P)
    if np.any(np.abs(x) > xs * (1 + 1e-12)):
        raise ConfigError("unloading branch: need -Q_max <= Q <= Q_max")
    K = 3.0 * mu * P / (16.0 * _positive("contact_radius", contact_radius)) * _positive("S", S)
    return K * (2.0 * (1.0 - (xs - x) / 2.0) ** (2.0 / 3.0) - (1.0 - xs) ** (2.0 / 3.0) - 1.0)


def fretting_loop_energy(Q_max: float, mu: float, P: float, contact_radius: float,
                         S: float) -> float:
    """Energy dissipated per full cycle Q_max -> -Q_max -> Q_max: the area of
    the Mindlin–Deresiewicz loop, integrated in closed form from
    :func:`mindlin_deresiewicz_unloading` and its mirror image:

        W = mu P K [ (24/5)(1 - (1 - x*)^(5/3)) - 4 x* (1 + (1 - x*)^(2/3)) ]

    with K = 3 mu P S / (16 a), x* = Q_max / (mu P).  For small amplitude
    W ~ S Q_max^3 / (36 a mu P) (cubic in the amplitude)."""
    xs = _ratio(Q_max, mu, P)
    K = 3.0 * mu * P / (16.0 * _positive("contact_radius", contact_radius)) * _positive("S", S)
    return mu * P * K * (
        24.0 / 5.0 * (1.0 - (1.0 - xs) ** (5.0 / 3.0)) - 4.0 * xs * (1.0 + (1.0 - xs) ** (2.0 / 3.0))
    )


def boussinesq_punch_force(radius: float, indentation: float, contact_modulus: float) -> float:
    """Rigid flat circular punch of radius a pressed by delta: F = 2 a E* delta."""
    return 2.0 * _positive("radius", radius) * _positive("contact_modulus", contact_modulus) * (
        _positive("indentation", indentation)
    )


def boussinesq_punch_pressure(r, radius: float, force: float) -> np.ndarray:
    """p(r) = F / (2 pi a sqrt(a^2 - r^2)) for r < a (singular at the rim), 0
    outside."""
    a = _positive("radius", radius)
    r = np.asarray(r, dtype=float)
    inside = r < a
    out = np.zeros_like(r)
    out[inside] = _positive("force", force) / (2.0 * math.pi * a * np.sqrt(a * a - r[inside] ** 2))
    return out


__all__ = [
    "effective_modulus",
    "tangential_compliance_factor",
    "Hertz",
    "hertz",
    "hertz_force",
    "cattaneo_mindlin_stick_radius",
    "cattaneo_mindlin_traction",
    "cattaneo_mindlin_displacement",
    "mindlin_deresiewicz_unloading",
    "fretting_loop_energy",
    "boussinesq_punch_force",
    "boussinesq_punch_pressure",
]
