"""Frictionless contact of an elastic sphere on a coated half-space: an
elastic layer of thickness t bonded on an elastic substrate, both
isotropic (the coated block's reference, docs/validation.md,
"Finite-element bodies").

Derived and computed here, independently of the boundary and finite
element solvers:

* :func:`surface_compliance`: the layered half-space's normal surface
  compliance in Fourier space, c(kt) / k (a normal pressure p̂ e^{ik·x}
  moves the surface by -c p̂ / k e^{ik·x}).  The plane-strain state
  ξ = (u_x, u_z, σ_xz / k, σ_zz / k) of a wave e^{ikx} obeys dξ/dζ = A ξ
  in ζ = k z with A constant in each material; the substrate's solutions
  that decay as z → -∞ are the dominant column space of e^{A L}
  (L = 40), carried to the surface through the layer by e^{A kt}, and the
  surface conditions (σ_xz = 0, σ_zz = -p) fix them.  Without a layer
  c = 2 (1 - ν²) / E (Boussinesq), which the tests check.
* :func:`sphere_on_coated_half_space`: the contact under a given normal
  force on a periodic grid (cell a/40, period 12.8 a, so the periodic
  images change the contact by about (a / period)³), the sphere's own
  compliance 2 (1 - ν_s²) / E_s added to the layered one (frictionless:
  the tangential coupling of dissimilar materials does no work), solved
  by Polonsky and Keer's constrained conjugate gradients (1999) with the
  exact sphere's gap R - sqrt(R² - r²).

Units: lengths in mm, moduli in N/mm² (any consistent set).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.interpolate
import scipy.linalg

from ...errors import ConfigError

_DECAY = 40.0  # ζ over which the substrate's growing modes are taken (e^-80 of the others)
_THICK = 25.0  # kt beyond which the layer is a half-space of its own (error e^-50)


def _state_matrix(youngs_modulus: float, poisson_ratio: float, scale: float) -> np.ndarray:
    """A (4, 4) of dξ/dζ = A ξ, ξ = (U, W, S / (k s), Z / (k s)) with the
    stresses in units of ``scale`` s (a modulus: A's entries are then of
    order one, and its exponentials keep their digits)."""
    E, nu = youngs_modulus / scale, poisson_ratio
    lam = E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu))
    mu = E / (2.0 * (1.0 + nu))
    M = lam + 2.0 * mu
    A = np.zeros((4, 4), complex)
    A[0, 1], A[0, 2] = -1j, 1.0 / mu                   # U' = S/mu - i W
    A[1, 0], A[1, 3] = -1j * lam / M, 1.0 / M          # W' = (Z - i lam U) / M
    A[2, 0], A[2, 3] = M - lam * lam / M, -1j * lam / M  # S' = (M - lam²/M) U - i lam Z / M
    A[3, 2] = -1j                                       # Z' = -i S
    return A


def _decaying_modes(A: np.ndarray) -> np.ndarray:
    """(4, 2): an orthonormal basis of the states that decay as z → -∞."""
    u, _, _ = np.linalg.svd(scipy.linalg.expm(A * _DECAY))
    return u[:, :2]


def _surface_value(modes: np.ndarray) -> float:
    """c = -W(0) of the state in span(``modes``) with S(0) = 0, Z(0) = -1."""
    c = np.linalg.solve(modes[2:4, :], np.array([0.0, -1.0]))
    return float(-(modes[1, :] @ c).real)


def _boussinesq(E: float, nu: float) -> float:
    """A homogeneous half-space's normal surface compliance c = 2 (1 - ν²) / E."""
    return 2.0 * (1.0 - nu * nu) / E


def _check(name: str, E, nu) -> tuple[float, float]:
    if not (isinstance(E, (int, float)) and math.isfinite(E) and E > 0):
        raise ConfigError(f"{name}: youngs_modulus must be a number > 0, got {E!r}")
    if not (isinstance(nu, (int, float)) and -1.0 < nu < 0.5):
        raise ConfigError(f"{name}: poisson_ratio must be in (-1, 0.5), got {nu!r}")
    return float(E), float(nu)


def surface_compliance(kt, layer: tuple[float, float], substrate: tuple[float, float]) -> np.ndarray:
    """c(kt) (compliance units: 1 / modulus) of a layer (E, ν) bonded on a
    substrate (E, ν), at wavenumbers k times the layer's thickness t; the
    surface compliance is c / k.  kt → 0: the substrate's 2 (1 - ν²) / E;
    kt → ∞: the layer's."""
    layer, substrate = _check("layer", *layer), _check("substrate", *substrate)
    s = substrate[0]
    Al = _state_matrix(*layer, s)
    Bs = _decaying_modes(_state_matrix(*substrate, s))
    thick = _surface_value(_decaying_modes(Al))
    kt = np.asarray(kt, dtype=float)
    out = np.empty(kt.shape)
    for i, x in np.ndenumerate(kt):
        out[i] = thick if x >= _THICK else _surface_value(scipy.linalg.expm(Al * x) @ Bs)
    return out / s


@dataclass(frozen=True)
class GridContact:
    """A contact's pressure on a periodic grid: ``pressure`` (n, n) at the
    cell centres ``x`` (n,) along both axes (the sphere's axis at the
    origin), cell ``dx``, and the ``normal_force`` (the approach of a
    periodic contact is not the half-space's: the grid has none)."""

    x: np.ndarray
    dx: float
    pressure: np.ndarray
    normal_force: float
    iterations: int

    def pressure_at(self, points) -> np.ndarray:
        """The pressure at points (m, 2 or 3; their x and y), bilinear."""
        f = scipy.interpolate.RegularGridInterpolator((self.x, self.x), self.pressure,
                                                      bounds_error=False, fill_value=0.0)
        return f(np.asarray(points, dtype=float)[:, :2])

    @property
    def peak_pressure(self) -> float:
        return float(self.pressure.max())

    @property
    def moment_radius(self) -> float:
        X, Y = np.meshgrid(self.x, self.x, indexing="ij")
        return moment_radius(X.ravel(), Y.ravel(), self.pressure.ravel(), np.full(X.size, 1.0))


def pressure_moments(x, y, pressure, weights) -> np.ndarray:
    """(2, 2): ∫ d dᵀ p dA / ∫ p dA, d = (x, y) from the pressure's
    centroid (negative pressures count as none); for Hertz's ellipse of
    semi-axes a, b: diag(a², b²) / 5 in its axes."""
    p = np.maximum(np.asarray(pressure, dtype=float), 0.0) * np.asarray(weights, dtype=float)
    d = np.column_stack([np.asarray(x, dtype=float), np.asarray(y, dtype=float)])
    d -= (p @ d) / p.sum()
    return (d * p[:, None]).T @ d / p.sum()


def moment_radius(x, y, pressure, weights) -> float:
    """sqrt(5/2 ∫ r² p dA / ∫ p dA) about the pressure's centroid: the
    contact radius a for Hertz's pressure (the second moment is 2 a² / 5),
    a size that weighs the contact's edge, where a mesh resolves it least,
    least."""
    return float(math.sqrt(2.5 * np.trace(pressure_moments(x, y, pressure, weights))))


def sphere_on_coated_half_space(
    normal_force: float,
    radius: float,
    sphere: tuple[float, float],
    layer: tuple[float, float],
    thickness: float,
    substrate: tuple[float, float],
    cells_per_radius: int = 40,
    tolerance: float = 1e-10,
) -> GridContact:
    """The frictionless contact of a sphere (``radius``, material (E, ν))
    pressed by ``normal_force`` on a layer (E, ν) of ``thickness`` bonded on
    a substrate (E, ν) (module docstring).  ``thickness = 0``: the
    substrate alone."""
    for name, v in (("normal_force", normal_force), ("radius", radius)):
        if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
            raise ConfigError(f"{name} must be a number > 0, got {v!r}")
    if not (isinstance(thickness, (int, float)) and math.isfinite(thickness) and thickness >= 0):
        raise ConfigError(f"thickness must be a number >= 0, got {thickness!r}")
    sphere_c = _boussinesq(*_check("sphere", *sphere))
    layer, substrate = _check("layer", *layer), _check("substrate", *substrate)
    stiffest = min(_boussinesq(*layer), _boussinesq(*substrate))
    # the grid from the Hertz radius with the stiffer of the two materials
    # (the contact is larger than that)
    a = (3.0 * normal_force * radius * (sphere_c + stiffest) / 8.0) ** (1.0 / 3.0)
    dx = a / cells_per_radius
    n = 512 * max(1, math.ceil(cells_per_radius / 40))
    x = (np.arange(n) - n // 2) * dx
    kx = 2.0 * np.pi * np.fft.fftfreq(n, dx)
    ky = 2.0 * np.pi * np.fft.rfftfreq(n, dx)
    k = np.hypot(kx[:, None], ky[None, :])
    if thickness > 0:
        kt = np.geomspace(1e-4, _THICK, 400)
        table = scipy.interpolate.CubicSpline(np.log(kt), surface_compliance(kt, layer, substrate))
        kth = np.clip(k * thickness, kt[0], kt[-1])
        c = table(np.log(kth))
    else:
        c = np.full(k.shape, _boussinesq(*substrate))
    kernel = np.zeros(k.shape)
    kernel[k > 0] = (c[k > 0] + sphere_c) / k[k > 0]  # the mean is the approach's

    def displacement(p):
        return np.fft.irfft2(kernel * np.fft.rfft2(p), s=p.shape)

    X, Y = np.meshgrid(x, x, indexing="ij")
    r2 = X * X + Y * Y
    if math.sqrt(r2.max()) >= radius:
        raise ConfigError("the contact grid reaches beyond the sphere: the force is too "
                          "large for its radius")
    gap0 = radius - np.sqrt(radius * radius - r2)
    p, it = _polonsky_keer(displacement, gap0, normal_force / (dx * dx), tolerance)
    return GridContact(x, dx, p, float(p.sum() * dx * dx), it)


def _polonsky_keer(displacement, gap0, total, tolerance, max_iterations=5000):
    """Pressures p >= 0 with sum p = ``total`` and a uniform gap where
    p > 0, not smaller outside (Polonsky and Keer, Wear 231, 1999: the
    conjugate gradient on the contact set, the set changing inside it)."""
    p = np.where(gap0 <= np.quantile(gap0, 0.01), 1.0, 0.0)
    p *= total / p.sum()
    t = np.zeros_like(p)
    G_old, conj = 1.0, False
    for it in range(1, max_iterations + 1):
        on = p > 0
        g = displacement(p) + gap0
        g -= g[on].mean()
        G = float(np.sum(g[on] ** 2))
        t = np.where(on, g + (G / G_old if conj else 0.0) * t, 0.0)
        G_old = G
        r = displacement(t)
        r -= r[on].mean()
        tau = float(np.sum(g[on] * t[on]) / np.sum(r[on] * t[on]))
        p_old = p
        p = np.maximum(p - tau * t, 0.0)
        overlap = (p == 0) & (g < 0)
        conj = not overlap.any()
        if not conj:
            p[overlap] -= tau * g[overlap]
        p *= total / p.sum()
        if np.abs(p - p_old).sum() <= tolerance * total:
            return p, it
    raise ConfigError(f"the coated half-space's contact did not converge in {max_iterations} "
                      "iterations")


__all__ = ["surface_compliance", "sphere_on_coated_half_space", "GridContact", "pressure_moments",
           "moment_radius"]
