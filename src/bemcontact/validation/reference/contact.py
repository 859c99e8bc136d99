"""Classical analytic contact solutions (half-spaces, small strain).

Sources (formulas only): K. L. Johnson, *Contact Mechanics*, Cambridge 1985,
§3.4 (flat punch), §4.2 (Hertz), §7.2 (Cattaneo–Mindlin), §7.4
(Mindlin–Deresiewicz unloading and the fretting loop); D. A. Spence, "The
Hertz contact problem with finite friction", J. Elasticity 5 (1975)
297–319 (dissimilar spheres under a growing normal load, derived below in
the uncoupled approximation); design notes ``validation.md``.  Units are any consistent set (docs/theory.md); pressures
and tractions > 0 as in the package conventions (pressure compressive).

Notation: P normal force, Q tangential force (0 <= |Q| < mu P), R effective
radius 1/R = 1/R1 + 1/R2, E* = 1 / ((1 - nu1^2)/E1 + (1 - nu2^2)/E2),
a contact radius, p0 peak pressure, G shear modulus.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.integrate import quad
from scipy.optimize import brentq
from scipy.special import ellipe, ellipk, ellipkm1

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


# --------------------------------------------------------------------------- Spence


def dundurs_beta(E1: float, nu1: float, E2: float, nu2: float) -> float:
    """Dundurs' second parameter of bodies 1 and 2 (E2 = math.inf: rigid),

        beta = [(1 - 2 nu1)/G1 - (1 - 2 nu2)/G2] / (2 [(1 - nu1)/G1 + (1 - nu2)/G2]),

    G = E / (2 (1 + nu)).  |beta| <= 1/2 (a rigid body on nu = 0); beta > 0
    when a normal pressure draws body 1's surface inward (toward the axis of
    an axisymmetric load) more than body 2's: the radial displacement
    difference u_r1 - u_r2 of two half-spaces under a common pressure p is
    -beta K (1/r) int_0^r p s ds with K = (1 - nu1)/G1 + (1 - nu2)/G2."""
    def parts(E, nu):
        if math.isinf(E):
            return 0.0, 0.0
        G = _positive("youngs_modulus", E) / (2.0 * (1.0 + nu))
        return (1.0 - 2.0 * nu) / G, (1.0 - nu) / G

    a1, k1 = parts(E1, nu1)
    a2, k2 = parts(E2, nu2)
    if k1 + k2 == 0.0:
        raise ConfigError("dundurs_beta: both bodies rigid")
    return (a1 - a2) / (2.0 * (k1 + k2))


def _spence_ratio(k: float) -> float:
    """|beta| / mu as a function of c/a = k (decreasing from inf at 0 to 0 at 1)."""
    return k * ellipkm1(k * k) / math.atanh(k)


def _spence_k(beta: float, mu: float) -> float:
    b = abs(float(beta))
    mu = float(mu)
    if not (math.isfinite(b) and b <= 0.5 and math.isfinite(mu) and mu >= 0):
        raise ConfigError(f"Spence: need |beta| <= 1/2 and mu >= 0, got beta={beta!r}, mu={mu!r}")
    if b == 0.0:
        return 1.0  # no tangential traction: nothing slips
    if mu == 0.0:
        return 0.0
    x = b / mu
    if x > 700.0:  # c/a ~ 4 exp(-x) underflows
        return 0.0
    lo = min(4.0 * math.exp(-x - 2.0), 0.5)
    hi = 1.0 - 1e-15
    if _spence_ratio(hi) >= x:
        return hi
    return brentq(lambda k: _spence_ratio(k) - x, lo, hi, xtol=1e-15, rtol=1e-15)


def spence_stick_radius(contact_radius: float, beta: float, mu: float) -> float:
    """Radius c of the central stick zone of two dissimilar elastic bodies
    (Dundurs parameter ``beta``, friction coefficient ``mu``) pressed
    together by a monotonically growing normal load with a Hertz pressure
    on the disc of radius a (Spence's problem).  The loading is
    self-similar: c/a is fixed, the root k of

        |beta| / mu = k K(sqrt(1 - k^2)) / artanh(k)

    (K the complete elliptic integral of the first kind of modulus
    sqrt(1 - k^2)); c/a -> 1 as beta/mu -> 0 and c/a ~ 4 exp(-|beta|/mu)
    as beta/mu -> inf.

    Derivation (uncoupled, or Goodman, approximation: the shear's effect on
    the pressure is neglected, so p is Hertz's): with K = (1 - nu1)/G1 +
    (1 - nu2)/G2 the relative radial displacement of the surfaces is
    K (U[q] - beta U[p]) with U[p] = (1/r) int_0^r p s ds at radius r and U[q] the
    radial displacement of a unit-compliance half-space under the radial
    shear q on body 1.  Under growth da of the contact radius a stuck point
    keeps its relative position, U[dq] = beta dU[p] on r < c, and a slipping
    one carries dq = sign(beta) mu dp on c < r < a.  With U[q] = -d/dr W[phi],
    phi(s) = int_s^inf q, W the unit-compliance normal displacement (a
    Hankel-transform identity), this is an axisymmetric mixed problem for
    phi whose Abel function h is known piecewise: from the stick condition
    on t < c, h'(t) = -(beta C a/pi) ln((a + t)/(a - t)), and from the slip
    traction on t > c, h'(t) = -(2 mu C/pi) t K(sqrt(1 - t^2/a^2)) (C = p0/a).
    A jump of h' at c would make dq infinite there (~ (c - r)^(-1/2)), so c
    is where they agree: the equation above."""
    return _positive("contact_radius", contact_radius) * _spence_k(beta, mu)


_GL_X, _GL_W = np.polynomial.legendre.leggauss(12)


def _spence_increment(s: float, k: float, b: float) -> float:
    """Radial shear increment per unit growth of a, dq/da / (mu p0/a), at
    s = r/a for beta/mu = b >= 0 (mu p0/a / sqrt(1 - s^2) in the slip zone)."""
    L = math.sqrt(1.0 - s * s)
    if s >= k:
        return 1.0 / L
    u0 = math.sqrt(k * k - s * s)
    stick = 2.0 * b / math.pi * math.atanh(u0 / L) / L

    def slip(u):
        m = 1.0 - s * s - u * u  # 1 - t^2, t = sqrt(s^2 + u^2) in (k, 1)
        return 0.5 if m < 1e-12 else 2.0 / math.pi * (ellipk(m) - ellipe(m)) / m

    return (1.0 / L - stick - quad(slip, u0, L, epsabs=1e-14, epsrel=1e-12, limit=200)[0]) / s


class _SpenceTable:
    """q(r)/(mu p0) = rho [int_rho^k psi(t)/t^2 dt + sqrt(1 - k^2)/k] on the
    stick zone rho = r/a < k (psi from :func:`_spence_increment`; the slip
    zone part integrated in closed form), by 12-point Gauss-Legendre on a
    grid geometric in t near 0 (psi ~ alpha t there) and uniform in
    theta = asin(t/k) toward k (psi ~ sqrt(k - t))."""

    def __init__(self, k: float, b: float):
        self.k, self.b = k, b
        self.t0 = 1e-3 * k
        g = np.geomspace(self.t0, 0.1 * k, 15)
        th = np.linspace(math.asin(0.1), 0.5 * math.pi, 41)
        self.nodes = np.concatenate([g[:-1], k * np.sin(th)])
        self.nodes[-1] = k
        pieces = [self._piece(a, c) for a, c in zip(self.nodes[:-1], self.nodes[1:])]
        # F[j] = int_{nodes[j]}^k psi/t^2
        self.F = np.concatenate([np.cumsum(pieces[::-1])[::-1], [0.0]])
        self.alpha = _spence_increment(self.t0, k, b) / self.t0

    def _piece(self, lo: float, hi: float) -> float:
        k = self.k
        if hi <= 0.1 * k * (1 + 1e-12):  # log variable
            x = 0.5 * (math.log(hi) - math.log(lo)) * _GL_X + 0.5 * (math.log(hi) + math.log(lo))
            t = np.exp(x)
            f = [_spence_increment(v, k, self.b) / v for v in t]  # psi/t^2 * dt/dx (= t)
            return 0.5 * (math.log(hi) - math.log(lo)) * float(np.dot(_GL_W, f))
        a, c = math.asin(min(lo / k, 1.0)), math.asin(min(hi / k, 1.0))
        th = 0.5 * (c - a) * _GL_X + 0.5 * (c + a)
        t = k * np.sin(th)
        f = [_spence_increment(v, k, self.b) / v**2 * k * math.cos(x) for v, x in zip(t, th)]
        return 0.5 * (c - a) * float(np.dot(_GL_W, f))

    def __call__(self, rho: float) -> float:
        k = self.k
        tail = math.sqrt(1.0 - k * k) / k
        if rho <= 0.0:
            return 0.0
        if rho < self.t0:
            return rho * (self.F[0] + self.alpha * math.log(self.t0 / rho) + tail)
        j = int(np.searchsorted(self.nodes, rho, side="right")) - 1
        j = min(j, len(self.nodes) - 2)
        return rho * (self._piece(rho, self.nodes[j + 1]) + self.F[j + 1] + tail)


def spence_traction(r, contact_radius: float, peak_pressure: float, beta: float,
                    mu: float) -> np.ndarray:
    """Radial shear traction q_r(r) on body 1 (> 0 pointing away from the
    axis) at the end of Spence's monotonic loading to the Hertz contact of
    radius a and peak pressure p0 (the uncoupled approximation of
    :func:`spence_stick_radius`): sign(beta) mu p(r) in the slip annulus
    c < r < a and, in the stick zone, the sum of the point's increments over
    the loading history (a' from r to a; self-similarity turns it into)

        q(r) = sign(beta) mu p0 rho [int_rho^k psi(t)/t^2 dt + sqrt(1 - k^2)/k],
        rho = r/a,

    psi(s) = [1/sqrt(1 - s^2) - (2 b/pi) artanh(sqrt((k^2 - s^2)/(1 - s^2)))
    / sqrt(1 - s^2) - int_{sqrt(k^2 - s^2)}^{sqrt(1 - s^2)} (2/pi) (K(m) -
    E(m))/m du] / s, m = 1 - s^2 - u^2, b = |beta|/mu, k = c/a (the stuck
    points' increment per unit growth of a, in units mu p0/a; K, E complete
    elliptic integrals of parameter m).  q is continuous at c (= mu p(c)),
    below mu p inside and ~ rho ln(rho) at the centre.  Body 2 carries -q_r."""
    a = _positive("contact_radius", contact_radius)
    p0 = _positive("peak_pressure", peak_pressure)
    k = _spence_k(beta, mu)
    rho = np.asarray(r, dtype=float) / a
    out = np.zeros_like(rho)
    if beta == 0 or mu == 0:  # no shear: identical (1 - 2 nu)/G, or frictionless
        return out
    slip = (rho >= k) & (rho < 1.0)
    out[slip] = np.sqrt(1.0 - rho[slip] ** 2)
    stick = rho < k
    if np.any(stick) and k > 0:
        table = _SpenceTable(k, abs(float(beta)) / float(mu))
        out[stick] = [table(float(x)) for x in np.abs(rho[stick])]
    return math.copysign(1.0, beta) * float(mu) * p0 * out


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
    "dundurs_beta",
    "spence_stick_radius",
    "spence_traction",
]
