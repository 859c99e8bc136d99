"""Influence coefficients of the elastic half-space on a grid of rectangular cells.

A traction that is uniform over a rectangular cell of the surface z = 0 of a
homogeneous isotropic half-space (shear modulus G, Poisson's ratio ν) moves the
surface at a point by Love's closed-form integral of the Boussinesq–Cerruti
point-load solution over the rectangle (Love 1929; Johnson, *Contact Mechanics*,
1985, ch. 3; Kalker, *Three-dimensional elastic bodies in rolling contact*,
1990).  This module gives those integrals and the 3 × 3 blocks they form on a
regular grid.

Sign convention (the one statement of it; docs/theory.md repeats it):

* z is normal to the plane and points **into** the half-space (the body
  occupies z > 0); x, y, z are right-handed.
* The traction (p_x, p_y, p_z) is the force per area applied **to** the body:
  tangential components in +x and +y; p_z = p is the pressure, p > 0
  compressive (it pushes into the body: the traction is −p times the outward
  normal −e_z).
* The displacement (u_x, u_y, u_z) is that of the body's surface; u_z > 0 is
  into the body (the normal approach).

For two bodies the operator gives the relative displacement in the contact
frame's terms (docs/theory.md, "Signs"): body 1 lies on the side z < 0, body 2
on z > 0, z is the frame normal from body 1 into body 2, the traction acts on
body 2 (body 1 receives its negative) and the displacement is that of body 2
relative to body 1, ``k = u_2 − u_1`` (k_z > 0 opens the gap).  A single
half-space is body 2 against a rigid body 1.

The surface Green's function (displacement at offset (x, y) = observation point
minus load point, r = √(x² + y²), per unit force), summed over the two bodies:

    C_xx = [S / r + T x² / r³] / (2π),   C_yy = [S / r + T y² / r³] / (2π)
    C_zz = S / (2π r),                   C_xy = C_yx = T x y / (2π r³)
    C_xz = −C_zx = K x / (π r²),         C_yz = −C_zy = K y / (π r²)

with the composite compliances (:class:`Compliance`)

    S = Σ_a (1 − ν_a) / G_a  (= 2 / E*),    T = Σ_a ν_a / G_a,
    K = ¼ [(1 − 2ν_1) / G_1 − (1 − 2ν_2) / G_2]   (Kalker's difference parameter).

One half-space (body 2 alone): S = (1 − ν)/G, T = ν/G, K = −(1 − 2ν)/(4G), i.e.
u_z = (1 − ν) P / (2π G r) under a normal force P, and the surface is drawn
radially towards the force (u_x = −(1 − 2ν) P x / (4π G r²)).  K ≠ 0 couples the
normal and tangential problems of dissimilar bodies (Dundurs' β = −2K / S).

A block is the integral of these kernels over a cell of half-widths (a, b),
written as the double difference over the cell's corners of antiderivatives F
with ∂²F/∂X∂Y = kernel (X, Y the corner offsets):

    1/r:     X asinh(Y/|X|) + Y asinh(X/|Y|)      x²/r³:  Y asinh(X/|Y|)
    y²/r³:   X asinh(Y/|X|)                       xy/r³:  −r
    x/r²:    ½ Y ln r² + X atan(Y/X)              y/r²:   ½ X ln r² + Y atan(X/Y)

(each term taken as 0 where its first factor is 0).  For a far cell the
double difference cancels leading digits: measured against extended precision,
the relative round-off of a coefficient is ≤ 7e-12 within 100 cells and ≤ 8e-10
within 1,000 (growing like ε (r/h)²), never above 2e-13 of the self-coefficient.
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass

import numpy as np

from ..errors import ConfigError
from ..settings import Key

#: The two material constants of a body, as ranges (the checks' one source).
SHEAR_MODULUS = Key("shear_modulus", "number", "shear modulus G (stress)", lo=0, lo_open=True)
POISSON_RATIO = Key("poisson_ratio", "number", "Poisson's ratio ν", lo=-1, lo_open=True, hi=0.5,
                    hi_open=True)

#: The grid's sizes.
CELLS = Key("cells", "integer", "number of cells along an axis", lo=1)
CELL_SIZE = Key("cell_size", "number", "cell size along an axis (length)", lo=0, lo_open=True)


def checked_number(owner: str, name: str, key: Key, value: object) -> float:
    """``value`` as a float if ``key`` accepts it, else a :class:`ConfigError`
    "<owner>: <name> must be ..., got <value>"."""
    if isinstance(value, numbers.Real) and not isinstance(value, bool):
        value = float(value)
    problem = key.violation(value)
    if problem is not None:
        raise ConfigError(f"{owner}: {name} {problem}, got {value!r}")
    return value


def checked_grid_size(owner: str, nx: object, ny: object, dx: object,
                      dy: object) -> tuple[int, int, float, float]:
    """(nx, ny, dx, dy) checked: integers ≥ 1 and finite sizes > 0."""
    counts = []
    for name, value in (("nx", nx), ("ny", ny)):
        if isinstance(value, numbers.Integral) and not isinstance(value, bool):
            value = int(value)
        problem = CELLS.violation(value)
        if problem is not None:
            raise ConfigError(f"{owner}: {name} {problem}, got {value!r}")
        counts.append(value)
    sizes = [checked_number(owner, name, CELL_SIZE, value)
             for name, value in (("dx", dx), ("dy", dy))]
    return counts[0], counts[1], sizes[0], sizes[1]


@dataclass(frozen=True)
class Compliance:
    """The composite compliances of the half-space operator (1/stress units).

    Build it with :meth:`half_space` (one body against a rigid one) or
    :meth:`pair` (two elastic bodies); the fields are the sums of the module
    docstring.

    Parameters
    ----------
    isotropic: S = Σ_a (1 − ν_a)/G_a, the coefficient of 1/r in every diagonal
        term (S = 2/E*).
    tangential: T = Σ_a ν_a/G_a, the coefficient of x_α x_β / r³ in the
        tangential block.
    difference: Kalker's difference parameter K = ¼ [(1 − 2ν_1)/G_1 −
        (1 − 2ν_2)/G_2], the coupling of normal and tangential (zero for
        identical bodies).  Body 2 carries the traction; Kalker's and CONTACT's
        body 1 is the one that carries it, so their K (made dimensionless with
        their combined G, 1/G = ½ (1/G_1 + 1/G_2)) is −G K for the same pair.
    """

    isotropic: float
    tangential: float
    difference: float

    def __post_init__(self) -> None:
        for name in ("isotropic", "tangential", "difference"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, numbers.Real) \
                    or not math.isfinite(value):
                raise ConfigError(f"Compliance: {name} must be a finite number, got {value!r}")
            object.__setattr__(self, name, float(value))
        if self.isotropic <= 0.0:
            raise ConfigError(f"Compliance: isotropic must be > 0, got {self.isotropic!r}")

    @classmethod
    def half_space(cls, shear_modulus: float, poisson_ratio: float) -> Compliance:
        """One half-space (shear modulus G > 0, −1 < ν < 0.5) loaded on its
        surface: S = (1 − ν)/G, T = ν/G, K = −(1 − 2ν)/(4G)."""
        G = checked_number("Compliance.half_space", "shear_modulus", SHEAR_MODULUS, shear_modulus)
        nu = checked_number("Compliance.half_space", "poisson_ratio", POISSON_RATIO, poisson_ratio)
        return cls((1.0 - nu) / G, nu / G, -(1.0 - 2.0 * nu) / (4.0 * G))

    @classmethod
    def pair(cls, shear_modulus_1: float, poisson_ratio_1: float, shear_modulus_2: float,
             poisson_ratio_2: float) -> Compliance:
        """Two half-spaces: body 1 on z < 0, body 2 on z > 0 (the traction
        acts on body 2); the operator gives u_2 − u_1."""
        owner = "Compliance.pair"
        G1 = checked_number(owner, "shear_modulus_1", SHEAR_MODULUS, shear_modulus_1)
        nu1 = checked_number(owner, "poisson_ratio_1", POISSON_RATIO, poisson_ratio_1)
        G2 = checked_number(owner, "shear_modulus_2", SHEAR_MODULUS, shear_modulus_2)
        nu2 = checked_number(owner, "poisson_ratio_2", POISSON_RATIO, poisson_ratio_2)
        return cls((1.0 - nu1) / G1 + (1.0 - nu2) / G2, nu1 / G1 + nu2 / G2,
                   0.25 * ((1.0 - 2.0 * nu1) / G1 - (1.0 - 2.0 * nu2) / G2))

    @property
    def contact_modulus(self) -> float:
        """E* = 2/S = 1 / Σ_a (1 − ν_a²)/E_a."""
        return 2.0 / self.isotropic

    @property
    def dundurs_beta(self) -> float:
        """Dundurs' second parameter β = −2K/S = [G_1(1 − 2ν_2) − G_2(1 − 2ν_1)]
        / [2 G_1(1 − ν_2) + 2 G_2(1 − ν_1)] (bodies numbered as here)."""
        return -2.0 * self.difference / self.isotropic


def _ratio(num: np.ndarray, den: np.ndarray) -> np.ndarray:
    """num/|den| where den ≠ 0, else 0 (the factor in front makes it 0 there)."""
    safe = np.where(den == 0.0, 1.0, np.abs(den))
    return np.where(den == 0.0, 0.0, num / safe)


def corner_antiderivatives(X: np.ndarray, Y: np.ndarray) -> np.ndarray:
    """The antiderivatives F of the module docstring at corner offsets (X, Y)
    (broadcast): shape (5, ...) in the order x²/r³, y²/r³, xy/r³, x/r², y/r²
    (1/r is the sum of the first two)."""
    X = np.asarray(X, dtype=float)
    Y = np.asarray(Y, dtype=float)
    X, Y = np.broadcast_arrays(X, Y)
    r2 = X * X + Y * Y
    r = np.sqrt(r2)
    log_r2 = np.log(np.where(r2 == 0.0, 1.0, r2))
    f_xx = Y * np.arcsinh(_ratio(X, Y))
    f_yy = X * np.arcsinh(_ratio(Y, X))
    f_xy = -r
    atan_yx = np.arctan(np.where(X == 0.0, 0.0, Y / np.where(X == 0.0, 1.0, X)))
    atan_xy = np.arctan(np.where(Y == 0.0, 0.0, X / np.where(Y == 0.0, 1.0, Y)))
    f_x = 0.5 * Y * log_r2 + X * atan_yx
    f_y = 0.5 * X * log_r2 + Y * atan_xy
    return np.stack([f_xx, f_yy, f_xy, f_x, f_y])


def rectangle_integrals(x: np.ndarray, y: np.ndarray, half_width_x: float,
                        half_width_y: float) -> np.ndarray:
    """∫∫ kernel(x − x', y − y') dx' dy' over the rectangle |x'| ≤ a, |y'| ≤ b
    (a, b the half-widths) for the kernels x²/r³, y²/r³, xy/r³, x/r², y/r²:
    shape (5, ...) for points (x, y) broadcast.  The integral of 1/r is the
    sum of the first two."""
    owner = "rectangle_integrals"
    a = checked_number(owner, "half_width_x", CELL_SIZE, half_width_x)
    b = checked_number(owner, "half_width_y", CELL_SIZE, half_width_y)
    x = np.asarray(x, dtype=float)
    y = np.asarray(y, dtype=float)
    return (corner_antiderivatives(x + a, y + b) - corner_antiderivatives(x - a, y + b)
            - corner_antiderivatives(x + a, y - b) + corner_antiderivatives(x - a, y - b))


def blocks_from_integrals(integrals: np.ndarray, compliance: Compliance) -> np.ndarray:
    """The 3 × 3 blocks (shape (..., 3, 3), rows u_x, u_y, u_z, columns p_x,
    p_y, p_z) from the geometric integrals (shape (5, ...))."""
    i_xx, i_yy, i_xy, i_x, i_y = integrals
    S, T, K = compliance.isotropic, compliance.tangential, compliance.difference
    c = 1.0 / (2.0 * math.pi)
    out = np.empty(i_xx.shape + (3, 3))
    out[..., 0, 0] = c * ((S + T) * i_xx + S * i_yy)
    out[..., 1, 1] = c * (S * i_xx + (S + T) * i_yy)
    out[..., 2, 2] = c * S * (i_xx + i_yy)
    out[..., 0, 1] = out[..., 1, 0] = c * T * i_xy
    out[..., 0, 2] = 2.0 * c * K * i_x
    out[..., 2, 0] = -out[..., 0, 2]
    out[..., 1, 2] = 2.0 * c * K * i_y
    out[..., 2, 1] = -out[..., 1, 2]
    return out


def influence_blocks(nx: int, ny: int, dx: float, dy: float, compliance: Compliance) -> np.ndarray:
    """The 3 × 3 influence blocks of every cell offset on an nx × ny grid of
    cells dx × dy, shape (2nx − 1, 2ny − 1, 3, 3): ``blocks[di + nx − 1,
    dj + ny − 1]`` is the displacement at the centre of cell (i, j) per unit
    uniform traction on cell (i − di, j − dj) (rows u_x, u_y, u_z; columns p_x,
    p_y, p_z; signs in the module docstring).

    The corner antiderivatives are evaluated once on the (2nx) × (2ny) lattice
    of corner offsets and differenced, so the cost is O(nx ny)."""
    nx, ny, dx, dy = checked_grid_size("influence_blocks", nx, ny, dx, dy)
    if not isinstance(compliance, Compliance):
        raise ConfigError(f"influence_blocks: compliance must be a Compliance, got "
                          f"{type(compliance).__name__}")
    X = (np.arange(-nx + 1, nx + 1) - 0.5) * dx
    Y = (np.arange(-ny + 1, ny + 1) - 0.5) * dy
    F = corner_antiderivatives(X[:, None], Y[None, :])
    integrals = F[:, 1:, 1:] - F[:, :-1, 1:] - F[:, 1:, :-1] + F[:, :-1, :-1]
    return blocks_from_integrals(integrals, compliance)
