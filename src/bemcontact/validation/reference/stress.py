"""Analytic stresses below a Hertz contact, frictionless and sliding.

Sources (formulas only): K. L. Johnson, *Contact Mechanics*, Cambridge 1985,
§3.4, eq. (3.44) (surface) and (3.45) (axis) for the Hertz pressure
p = p0 (1 - r^2/a^2)^(1/2); G. M. Hamilton, "Explicit equations for the
stresses beneath a sliding spherical contact", Proc. IMechE C 197 (1983)
53-59, for the whole field of that pressure and of the tangential traction
q = mu p along +x (the sphere sliding in +x over the body); Hamilton & Goodman,
J. Appl. Mech. 33 (1966) 371-376, for the potentials behind them.
Hamilton's equations are transcribed as they are widely reproduced (e.g. in
the contact-mechanics module of matscipy) and rearranged; the complex
identities and the near-axis treatment below are ours.  None is taken on
trust (the axis limits are checked in 60-digit arithmetic): every component is checked against the independent Love-rectangle
sums of :class:`bemcontact.halfspace.HalfSpaceStress`, the surface tractions
and equilibrium in ``tests/unit/validation/test_stress_reference.py``.

Conventions: those of :mod:`bemcontact.halfspace.stress`, so that the two can
be compared directly.  The body occupies z > 0 (body 2 of the contact frame,
z from body 1 into body 2); a point at depth d below the surface point
(x, y) is (x, y, d).  The contact is centred on the origin of the surface
z = 0.  The tractions act on the body: the pressure p > 0 pushes into it, the
shear q = mu p is along +x.  Stresses are Cauchy stresses in the units of p0,
tension positive (compression negative), ordered (s_xx, s_yy, s_zz, s_xy,
s_yz, s_xz); at the surface inside the contact s_zz = -p and s_xz = -q.
Depths must be >= 0.

Frictionless axis (r = 0, Johnson eq. 3.45), z the depth:

    s_z / p0 = -(1 + z^2/a^2)^-1
    s_r / p0 = s_t / p0 = -(1 + nu) [1 - (z/a) atan(a/z)] + (1/2) (1 + z^2/a^2)^-1

Frictionless surface (z = 0, Johnson eq. 3.44), s = 1 - r^2/a^2:

    r <= a:  s_r / p0 = (1 - 2 nu)/3 (a^2/r^2) [1 - s^(3/2)] - s^(1/2)
             s_t / p0 = -(1 - 2 nu)/3 (a^2/r^2) [1 - s^(3/2)] - 2 nu s^(1/2)
             s_z / p0 = -s^(1/2)
    r >= a:  s_r / p0 = -s_t / p0 = (1 - 2 nu) a^2 / (3 r^2),  s_z = 0

Hamilton's field, in units of the contact radius (x, y, z divided by a,
r^2 = x^2 + y^2):

    A = r^2 + z^2 - 1,  S = (A^2 + 4 z^2)^(1/2),  M = ((S + A)/2)^(1/2),
    N = ((S - A)/2)^(1/2),  phi = atan(1/M),
    G = M^2 - N^2 + z M - N,  H = 2 M N + M + z N

(M + iN = (r^2 + (z + i)^2)^(1/2) and G + iH = (M + iN)(M + iN + z + i)).
Per unit p0 (the pressure):

    s_xx = (1 + nu) z phi + r^-2 [ (y^2 - x^2) r^-2 C - N (x^2 + 2 nu y^2) - M x^2 z / S ]
    s_yy = the same with x and y exchanged
    s_zz = -N + z M / S
    s_xy = x y r^-4 [ (1 - 2 nu)(-N r^2 + 2/3 N (S + 2A) - z (z N + M) + 2/3)
                      + z (-M r^2 / S - z N + M) ]
    s_xz = x z W,  s_yz = y z W,  W = z H / (G^2 + H^2) - N / S
    with C = (1 - nu) N z^2 - (1 - 2 nu)/3 (N S + 2 A N + 1) - nu M z;

per unit q0 = mu p0 (the shear along +x), with c = 1 - 2 nu,
B = -c (S/6 + A/3) - (z^2 + 3)/2, e_x = 3/2 - 2 x^2/r^2, h_x = 1/2 - 2 x^2/r^2,
h_y = 1/2 - 2 y^2/r^2:

    s_xx = -(nu/4 + 1) x phi + x M r^-4 [ e_x (nu S - 2 nu A + z^2) + x^2 z^2 / S
               + 7/4 nu r^2 - 2 nu x^2 + r^2 ]
           + x z N r^-4 [ e_x B + x^2 / S - nu r^2 / 4 - 7/4 r^2 ] + 4/3 c x z r^-4 e_x
    s_yy = -3/4 nu x phi + x M r^-4 [ h_y (nu (S - 2A + r^2) + z^2) + y^2 z^2 / S + 3/4 nu r^2 ]
           + x z N r^-4 [ h_y B + y^2 / S - 3/4 nu r^2 - r^2 / 4 ] + 4/3 c x z r^-4 h_y
    s_zz = x z N / (2 r^2) [ 1 - (r^2 + z^2 + 1) / S ]
    s_xy = (nu/2 - 1) y phi / 2 + y M r^-4 [ x^2 z^2 / S + nu ((S - 2A) h_x - 2 x^2 + r^2/4)
               + r^2 / 2 + z^2 h_x ]
           + y z N r^-4 [ h_x (B - r^2/2) + nu r^2 / 4 + x^2 / S - y^2 / 2 - 3/2 x^2 ]
           + 4/3 c y z r^-4 h_x
    s_yz = x y z / (2 r^4) [ M (1 + (z^2 - 3 - r^2) / S) / 2 + z N (-3 + (5 + z^2 + r^2) / S) / 2 ]
    s_xz = 3/2 z phi + z M r^-2 (1 + x^2/r^2 - x^2/S)
           + N r^-2 [ -3/4 (S + 2A) + z^2 - (3 + r^2)/4 + z^2 h_x / 2 ]

On the axis (the limits r -> 0) the shear's only non-zero component is
s_xz / q0 = -1 + 3/2 z atan(1/z) - z^2 / (2 (1 + z^2)), and the pressure's
field is Johnson's above.  At the surface the formulas reduce to s_zz = -p,
s_xz = -q inside the contact and give the trailing-edge tension
s_xx(-a, 0, 0) = p0 [(1 - 2 nu)/3 + (4 + nu) pi mu / 8].

Numerics.  The terms in r^-4 cancel as r -> 0: evaluated as written the
round-off grows like eps (l/r)^3 (l = (a^2 + z^2)^(1/2)).  Within r < l/4 of
the axis the field is therefore interpolated along the line through the axis
and the point from 17 Chebyshev points on |t| <= l/4 (the middle one on the
axis, where the limits above are used); the field is analytic in t for
|t| < l (its singularities, M + iN = 0, lie at |t| = l), so the interpolant
converges like 7.9^-17.  Far from the contact the O(1) terms cancel to a
field of order (a/R)^2 p0: the absolute round-off grows roughly like
eps (R/a)^3 p0.  Against the same formulas in 60-digit arithmetic the
absolute error is <= 2e-12 p0 (per unit p0 and per unit q0) within R < 5a,
near the axis included, and 1e-10 p0 at R = 30 a.  Surface points (z = 0) are
evaluated at the depth 1e-30 a, where the formulas are regular also on the
contact edge r = a (0/0 at z = 0); the field is continuous there and changes
by < 1e-14 p0.
"""

from __future__ import annotations

import math
from typing import Callable, NamedTuple

import numpy as np
from scipy.optimize import brentq

from ...errors import ConfigError

#: Chebyshev points (first kind) of the near-axis interpolation; odd, so the
#: middle one lies on the axis.
_NODES = 17
_K = np.arange(_NODES)
_CHEBYSHEV = np.cos((2 * _K + 1) * np.pi / (2 * _NODES))
_CHEBYSHEV[_NODES // 2] = 0.0
_BARYCENTRIC = (-1.0) ** _K * np.sin((2 * _K + 1) * np.pi / (2 * _NODES))

#: The interpolation radius as a fraction of l = (a^2 + z^2)^(1/2).
_NEAR_AXIS = 0.25

#: The depth (in units of a) at which surface points are evaluated.
_SURFACE_DEPTH = 1e-30


def _positive(name: str, value: object) -> float:
    v = float(value)
    if not (math.isfinite(v) and v > 0.0):
        raise ConfigError(f"{name} must be a finite number > 0, got {value!r}")
    return v


def _poisson(value: object) -> float:
    v = float(value)
    if not (math.isfinite(v) and -1.0 < v < 0.5):
        raise ConfigError(f"poisson_ratio must satisfy -1 < nu < 0.5, got {value!r}")
    return v


def _non_negative_array(name: str, value: object) -> np.ndarray:
    v = np.asarray(value, dtype=float)
    if not np.all(np.isfinite(v)) or np.any(v < 0.0):
        raise ConfigError(f"{name} must be finite and >= 0 (depths and radii; the body "
                          f"occupies z > 0), got {value!r}")
    return v


# --------------------------------------------------------------------- frictionless Hertz


def _one_minus_x_atan(x: np.ndarray) -> np.ndarray:
    """1 - x atan(1/x) for x >= 0, without cancellation for large x
    (series u^2/3 - u^4/5 + ... in u = 1/x for x > 10, error < 1e-19)."""
    x = np.asarray(x, dtype=float)
    big = x > 10.0
    out = 1.0 - x * np.arctan2(1.0, x)
    if np.any(big):
        u2 = 1.0 / x[big] ** 2
        series = np.zeros_like(u2)
        for k in range(9, 0, -1):  # Horner: sum_k (-1)^(k+1) u^(2k) / (2k + 1)
            series = u2 * ((-1.0) ** (k + 1) / (2 * k + 1) + series)
        out[big] = series
    return out


def _axis_unit(z: np.ndarray, nu: float) -> tuple[np.ndarray, np.ndarray]:
    """s_z and s_r per p0 on the axis at depths z (units of a)."""
    w = 1.0 / (1.0 + z * z)
    return -w, -(1.0 + nu) * _one_minus_x_atan(z) + 0.5 * w


class HertzAxisStresses(NamedTuple):
    """The frictionless Hertz stresses on the axis (stress units of p0)."""

    #: s_z at the depths asked for (compression negative).
    sigma_z: np.ndarray
    #: s_r = s_theta at the depths asked for.
    sigma_r: np.ndarray
    #: max over z >= 0 of tau1 = |s_z - s_r| / 2.
    max_shear: float
    #: the depth of that maximum (length units of a).
    max_shear_depth: float


def hertz_axis_stresses(z, contact_radius: float, peak_pressure: float,
                        poisson_ratio: float) -> HertzAxisStresses:
    """The stresses on the axis below a frictionless Hertz contact (Johnson
    eq. 3.45, module docstring) at depths ``z`` >= 0 (array-like, length
    units), and the maximum of the principal shear tau1 = |s_z - s_r|/2 on
    the axis with its depth: the root of d tau1/dz (Brent, to 1e-15 a)
    bracketed by the best of 401 samples of [0, 4a] (0.31 p0 at 0.48 a for
    nu = 0.3; tau1 rises from (1/2 - nu) p0 / 2 at z = 0, slope (1 + nu) pi/4 p0/a,
    and decays like a^2/z^2)."""
    a = _positive("contact_radius", contact_radius)
    p0 = _positive("peak_pressure", peak_pressure)
    nu = _poisson(poisson_ratio)
    zu = _non_negative_array("z", z) / a

    def tau(t):
        sz, sr = _axis_unit(np.atleast_1d(t), nu)
        return 0.5 * (sr - sz)  # s_r > s_z on the axis: (1/2 - nu) p0 at z = 0, -> 0 below

    def slope(t):  # d tau / dz, with d/dz [z atan(1/z)] = atan(1/z) - z/(1 + z^2)
        w = 1.0 / (1.0 + t * t)
        return 0.5 * ((1.0 + nu) * (math.atan2(1.0, t) - t * w) - 3.0 * t * w * w)

    grid = np.linspace(0.0, 4.0, 401)
    k = int(np.argmax(tau(grid)))
    lo, hi = grid[max(k - 1, 0)], grid[k + 1]
    zm = brentq(slope, lo, hi, xtol=1e-15, rtol=4 * np.finfo(float).eps)
    sz, sr = _axis_unit(zu, nu)
    return HertzAxisStresses(p0 * sz, p0 * sr, p0 * float(tau(zm)[0]), a * float(zm))


class HertzSurfaceStresses(NamedTuple):
    """The frictionless Hertz stresses on the surface (stress units of p0)."""

    sigma_r: np.ndarray
    sigma_theta: np.ndarray
    sigma_z: np.ndarray


def hertz_surface_stresses(r, contact_radius: float, peak_pressure: float,
                           poisson_ratio: float) -> HertzSurfaceStresses:
    """The radial, hoop and normal stresses on the surface z = 0 of a
    frictionless Hertz contact at radii ``r`` >= 0 (array-like, length units),
    inside and outside the contact (Johnson eq. 3.44, module docstring).
    s_r reaches its largest tension (1 - 2 nu) p0 / 3 at r = a; at r = 0,
    s_r = s_theta = -(1 + 2 nu) p0 / 2.  Inside, (a^2/r^2)(1 - s^(3/2)) is
    evaluated as (1 + u + u^2)/(1 + u), u = s^(1/2), free of cancellation."""
    a = _positive("contact_radius", contact_radius)
    p0 = _positive("peak_pressure", peak_pressure)
    nu = _poisson(poisson_ratio)
    rho2 = (_non_negative_array("r", r) / a) ** 2
    inside = rho2 <= 1.0
    u = np.sqrt(np.where(inside, 1.0 - rho2, 0.0))
    with np.errstate(divide="ignore"):
        outer = (1.0 - 2.0 * nu) / (3.0 * rho2)
    lam = (1.0 - 2.0 * nu) / 3.0 * (1.0 + u + u * u) / (1.0 + u)
    sr = np.where(inside, lam - u, outer)
    st = np.where(inside, -lam - 2.0 * nu * u, -outer)
    sz = -u
    return HertzSurfaceStresses(p0 * sr, p0 * st, p0 * sz)


# --------------------------------------------------------------------- Hamilton (1983)


def _hamilton_unit(x, y, z, nu, sqrt: Callable, acot: Callable) -> tuple[tuple, tuple]:
    """Hamilton's explicit field off the axis (r > 0), lengths in units of a:
    ((6 components per p0 of the pressure), (6 per q0 of the shear along +x)),
    each ordered xx, yy, zz, xy, yz, xz.  Written with integer constants and
    the given ``sqrt`` and ``acot`` (arccot, = atan(1/M) for M >= 0) only, so
    the tests can evaluate it in extended precision (``decimal``)."""
    x2, y2, z2 = x * x, y * y, z * z
    r2 = x2 + y2
    r4 = r2 * r2
    A = r2 + z2 - 1
    S = sqrt(A * A + 4 * z2)
    M = sqrt((S + A) / 2)
    N = sqrt((S - A) / 2)
    phi = acot(M)
    G = M * M - N * N + z * M - N
    H = 2 * M * N + M + z * N
    c = 1 - 2 * nu
    # the pressure p0 (1 - r^2)^(1/2)
    C = (1 - nu) * N * z2 - c * (N * S + 2 * A * N + 1) / 3 - nu * M * z
    p_xx = (1 + nu) * z * phi + ((y2 - x2) * C / r2 - N * (x2 + 2 * nu * y2) - M * x2 * z / S) / r2
    p_yy = (1 + nu) * z * phi + ((x2 - y2) * C / r2 - N * (y2 + 2 * nu * x2) - M * y2 * z / S) / r2
    p_zz = z * M / S - N
    p_xy = x * y * (c * (2 * (N * (S + 2 * A) + 1) / 3 - N * r2 - z * (z * N + M))
                    + z * (M - M * r2 / S - z * N)) / r4
    W = z * H / (G * G + H * H) - N / S
    p_yz = y * z * W
    p_xz = x * z * W
    # the shear q0 (1 - r^2)^(1/2) along +x
    B = -c * (S / 6 + A / 3) - (z2 + 3) / 2
    ex = (3 - 4 * x2 / r2) / 2
    hx = (1 - 4 * x2 / r2) / 2
    hy = (1 - 4 * y2 / r2) / 2
    q_xx = (-(nu + 4) * x * phi / 4
            + x * M * (ex * (nu * S - 2 * nu * A + z2) + x2 * z2 / S + 7 * nu * r2 / 4
                       - 2 * nu * x2 + r2) / r4
            + x * z * N * (ex * B + x2 / S - nu * r2 / 4 - 7 * r2 / 4) / r4
            + 4 * c * x * z * ex / (3 * r4))
    q_yy = (-3 * nu * x * phi / 4
            + x * M * (hy * (nu * (S - 2 * A + r2) + z2) + y2 * z2 / S + 3 * nu * r2 / 4) / r4
            + x * z * N * (hy * B + y2 / S - 3 * nu * r2 / 4 - r2 / 4) / r4
            + 4 * c * x * z * hy / (3 * r4))
    q_zz = x * z * N * (1 - (r2 + z2 + 1) / S) / (2 * r2)
    q_xy = ((nu - 2) * y * phi / 4
            + y * M * (x2 * z2 / S + nu * ((S - 2 * A) * hx - 2 * x2 + r2 / 4) + r2 / 2
                       + z2 * hx) / r4
            + y * z * N * (hx * (B - r2 / 2) + nu * r2 / 4 + x2 / S - y2 / 2 - 3 * x2 / 2) / r4
            + 4 * c * y * z * hx / (3 * r4))
    q_yz = x * y * z * (M * (1 + (z2 - 3 - r2) / S) + z * N * ((5 + z2 + r2) / S - 3)) / (4 * r4)
    q_xz = (3 * z * phi / 2 + z * M * (1 + x2 / r2 - x2 / S) / r2
            + N * (z2 - 3 * (S + 2 * A) / 4 - (3 + r2) / 4 + z2 * hx / 2) / r2)
    return (p_xx, p_yy, p_zz, p_xy, p_yz, p_xz), (q_xx, q_yy, q_zz, q_xy, q_yz, q_xz)


def _acot(m: np.ndarray) -> np.ndarray:
    return np.arctan2(1.0, m)


def _off_axis(x: np.ndarray, y: np.ndarray, z: np.ndarray, nu: float) -> np.ndarray:
    """:func:`_hamilton_unit` in float64: shape (..., 2, 6) (pressure, shear)."""
    p, q = _hamilton_unit(x, y, z, nu, np.sqrt, _acot)
    return np.stack([np.stack(p, -1), np.stack(q, -1)], -2)


def _on_axis(z: np.ndarray, nu: float) -> np.ndarray:
    """The limits r -> 0: shape (..., 2, 6)."""
    out = np.zeros(z.shape + (2, 6))
    sz, sr = _axis_unit(z, nu)
    out[..., 0, 0] = out[..., 0, 1] = sr
    out[..., 0, 2] = sz
    out[..., 1, 5] = 0.5 / (1.0 + z * z) - 1.5 * _one_minus_x_atan(z)
    return out


def _near_axis(x: np.ndarray, y: np.ndarray, z: np.ndarray, nu: float) -> np.ndarray:
    """The field at points 0 < r < l/4 by Chebyshev interpolation along the
    line through the axis and the point (module docstring): (m, 2, 6)."""
    r = np.hypot(x, y)
    half = _NEAR_AXIS * np.sqrt(1.0 + z * z)
    t = half[:, None] * _CHEBYSHEV[None, :]                    # (m, n) node abscissae
    values = np.empty(t.shape + (2, 6))
    off = np.ones(_NODES, dtype=bool)
    off[_NODES // 2] = False
    tx, ty = t[:, off] * (x / r)[:, None], t[:, off] * (y / r)[:, None]
    values[:, off] = _off_axis(tx, ty, np.broadcast_to(z[:, None], tx.shape), nu)
    values[:, _NODES // 2] = _on_axis(z, nu)
    d = r[:, None] - t
    hit = d == 0.0
    d = np.where(hit, 1.0, d)
    w = np.where(hit, 1.0, _BARYCENTRIC[None, :] / d)
    exact = hit.any(axis=1)
    w[exact] = hit[exact].astype(float)                        # a node itself: its value
    return np.einsum("mn,mnij->mij", w, values) / w.sum(axis=1)[:, None, None]


def _unit_field(x: np.ndarray, y: np.ndarray, z: np.ndarray, nu: float) -> np.ndarray:
    """Per p0 and per q0 at points in units of a (z > 0): (m, 2, 6)."""
    r = np.hypot(x, y)
    out = np.empty(x.shape + (2, 6))
    axis = r == 0.0
    near = ~axis & (r < _NEAR_AXIS * np.sqrt(1.0 + z * z))
    far = ~axis & ~near
    out[axis] = _on_axis(z[axis], nu)
    if np.any(near):
        out[near] = _near_axis(x[near], y[near], z[near], nu)
    if np.any(far):
        out[far] = _off_axis(x[far], y[far], z[far], nu)
    return out


def hamilton_sliding_sphere_stresses(points, contact_radius: float, peak_pressure: float,
                                     friction_coefficient: float,
                                     poisson_ratio: float) -> np.ndarray:
    """The stresses below a sphere sliding along +x: Hamilton's (1983) explicit
    field of the Hertz pressure p = p0 (1 - r^2/a^2)^(1/2) plus the shear
    q = mu p along +x acting on the body (module docstring: formulas, signs,
    accuracy).

    Parameters
    ----------
    points: (n, 3) = (x, y, depth), depth >= 0 into the body (the
        convention of :meth:`bemcontact.halfspace.HalfSpaceStress.at`),
        length units; the contact is centred on the origin.
    contact_radius: a > 0 (length units).
    peak_pressure: p0 > 0 (stress units).
    friction_coefficient: mu >= 0 (mu = 0: the frictionless Hertz field).
    poisson_ratio: nu, -1 < nu < 0.5 (the stresses do not depend on the
        shear modulus).

    Returns
    -------
    (n, 6) stresses (s_xx, s_yy, s_zz, s_xy, s_yz, s_xz), tension positive,
    in the units of p0."""
    a = _positive("contact_radius", contact_radius)
    p0 = _positive("peak_pressure", peak_pressure)
    mu = float(friction_coefficient)
    if not (math.isfinite(mu) and mu >= 0.0):
        raise ConfigError(f"friction_coefficient must be a finite number >= 0, got "
                          f"{friction_coefficient!r}")
    nu = _poisson(poisson_ratio)
    p = np.asarray(points, dtype=float)
    if p.ndim != 2 or p.shape[1] != 3:
        raise ConfigError(f"points must have shape (n, 3) = (x, y, depth), got {p.shape}")
    if not np.all(np.isfinite(p)):
        raise ConfigError("points must be finite")
    if np.any(p[:, 2] < 0.0):
        raise ConfigError(f"points must lie in the body, depth z >= 0, got min z = "
                          f"{float(p[:, 2].min())!r}")
    u = p / a
    z = np.maximum(u[:, 2], _SURFACE_DEPTH)
    f = _unit_field(np.ascontiguousarray(u[:, 0]), np.ascontiguousarray(u[:, 1]), z, nu)
    return p0 * (f[:, 0] + mu * f[:, 1])
