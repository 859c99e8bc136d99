"""Subsurface stresses of the elastic half-space under piecewise-constant
tractions on a regular grid of rectangular cells.

The stress tensor at a point inside the half-space due to a traction that is
uniform over a rectangular cell of the surface, in closed form: the
Boussinesq–Cerruti point-load stresses integrated over the rectangle (Love 1929
for the pressure; Johnson, *Contact Mechanics*, 1985, ch. 3, for the
potentials).  :class:`HalfSpaceStress` sums them over a :class:`Grid`: by FFT
on whole depth layers (a Toeplitz convolution per depth) or directly at
arbitrary points.

Conventions (axes and traction signs as :mod:`.influence`):

* The body occupies z > 0: a point at depth d below the surface point (x, y)
  is (x, y, d), in the grid's x, y (the grid lies in the plane z = 0).  This
  is body 2 of the contact frame (z from body 1 into body 2); a single
  half-space is body 2 against a rigid body 1.
* The traction (p_x, p_y, p_z) is the force per area applied to the body; p_z
  = p > 0 is a pressure (it pushes into the body).
* Stresses are Cauchy stresses in the stress units of the traction, tension
  positive (a pressure gives σ_zz < 0 beneath it), ordered
  (σ_xx, σ_yy, σ_zz, σ_xy, σ_yz, σ_xz).  At the surface σ_iz → −p_i beneath a
  loaded cell.  They do not depend on the shear modulus.
* Body 1 (z < 0, loaded by −p) is the half-space seen through the rotation
  R = diag(1, −1, −1): its stress at (x, y, −d) is that of this module at
  (x, −y, d) for the grid mirrored in y and the traction (−p_x, p_y, p_z), with
  σ_xy and σ_xz negated.

Formulas.  Love's representation (Johnson ch. 3) writes the field of a
surface traction through derivatives of Ω = z ln(ρ + z) − ρ (ρ the distance
from the load point), which is harmonic with ∂Ω/∂z = ln(ρ + z) and ∂²Ω/∂z² =
1/ρ.  Each point-load stress is a combination of z^k ∂_x^a ∂_y^b ∂_z^c Ω
(a + b + c = 3 + k); using ∇²Ω = 0, every term is brought to a form whose
integral over a rectangle is the double difference over its corners of an
elementary function F (∂²F/∂X∂Y = term, X, Y the corner offsets, observation
minus corner, ρ² = X² + Y² + z²):

    F0 = ln(ρ + z)           F1 = −X/(ρ + z)          F2 = −Y/(ρ + z)
    F3 = zX/(ρ(ρ + z))       F4 = zY/(ρ(ρ + z))       F5 = −z/ρ
    F6 = ln(X + ρ)           F7 = ln(Y + ρ)
    F8 = z²/(ρ(X + ρ))       F9 = z²/(ρ(Y + ρ))
    F10 = zY/(ρ(X + ρ))      F11 = zX/(ρ(Y + ρ))
    F12 = atan[XY(ρ − z)/(X²ρ + Y²z)]                  (∂²/∂X∂Y: ∂_x²∂_zΩ)
    F13 = atan[XY(ρ − z)/(Y²ρ + X²z)]                  (∂²/∂X∂Y: ∂_y²∂_zΩ)

and, per unit traction, 4π σ = (with F for the corner double differences)

    p_x:  σ_xx = 2F4 + 2F9 − 4νF2 + 4F7     σ_yy = −2F4 + 4νF2 + 4νF7
          σ_zz = −2F9                        σ_xy = −2F3 + 4νF1 + 2F6
          σ_yz = 2F5                         σ_xz = −2(F11 + F12 + F13)
    p_y:  x ↔ y (F1 ↔ F2, F3 ↔ F4, F6 ↔ F7, F8 ↔ F9, F10 ↔ F11, F12 ↔ F13,
          σ_xx ↔ σ_yy, σ_yz ↔ σ_xz)
    p_z:  σ_xx = −2F11 − 4νF13 − 2F12        σ_yy = −2F10 − 2F13 − 4νF12
          σ_zz = 2(F10 + F11 − F12 − F13)    σ_xy = 2F5 − 2(1 − 2ν)F0
          σ_yz = −2F8                        σ_xz = −2F9

(the pressure's σ_zz is Love's −(p/2π)[atan(XY/(zρ)) + XYz/ρ (1/(X² + z²) +
1/(Y² + z²))]).  The forms are evaluated without cancellation: ρ − z =
(X² + Y²)/(ρ + z), X + ρ = (Y² + z²)/(ρ − X) for X < 0; for z > 0 every F is
smooth.  For cells far from the point (distance r) the corner differences
cancel leading digits, a relative round-off of ~ε (r/h)² of that cell's
(small) contribution.
"""

from __future__ import annotations

import math
import numbers

import numpy as np
import scipy.fft

from ..errors import ConfigError
from .grid import Grid
from .influence import CELL_SIZE, POISSON_RATIO, checked_grid_size, checked_number

#: Number of corner functions F0 … F13.
_NF = 14

#: Corner-function values computed at once by :meth:`HalfSpaceStress.at`.
_CHUNK_VALUES = 1 << 20

#: Bytes a :class:`HalfSpaceStress` keeps of what does not depend on the
#: tractions (the depth kernels' spectra of :meth:`~HalfSpaceStress.layers`,
#: the corner sums of :meth:`~HalfSpaceStress.at`), for the same depths and
#: points asked again under other tractions (a run's load steps, the other
#: body of a pair of one Poisson ratio): the first asked are kept, up to
#: this budget.
KEEP_BYTES = 1 << 27


def _coefficients(nu: float) -> np.ndarray:
    """4π × the stress per unit traction as combinations of the corner
    functions: shape (6, 3, 14), [component, traction component, F]."""
    c = np.zeros((6, 3, _NF))
    xx, yy, zz, xy, yz, xz = range(6)
    # p_x
    c[xx, 0, [4, 9, 2, 7]] = [2.0, 2.0, -4.0 * nu, 4.0]
    c[yy, 0, [4, 2, 7]] = [-2.0, 4.0 * nu, 4.0 * nu]
    c[zz, 0, 9] = -2.0
    c[xy, 0, [3, 1, 6]] = [-2.0, 4.0 * nu, 2.0]
    c[yz, 0, 5] = 2.0
    c[xz, 0, [11, 12, 13]] = -2.0
    # p_y: the mirror x <-> y of p_x
    c[yy, 1, [3, 8, 1, 6]] = [2.0, 2.0, -4.0 * nu, 4.0]
    c[xx, 1, [3, 1, 6]] = [-2.0, 4.0 * nu, 4.0 * nu]
    c[zz, 1, 8] = -2.0
    c[xy, 1, [4, 2, 7]] = [-2.0, 4.0 * nu, 2.0]
    c[xz, 1, 5] = 2.0
    c[yz, 1, [10, 13, 12]] = -2.0
    # p_z
    c[xx, 2, [11, 13, 12]] = [-2.0, -4.0 * nu, -2.0]
    c[yy, 2, [10, 13, 12]] = [-2.0, -2.0, -4.0 * nu]
    c[zz, 2, [10, 11, 12, 13]] = [2.0, 2.0, -2.0, -2.0]
    c[xy, 2, [5, 0]] = [2.0, -2.0 * (1.0 - 2.0 * nu)]
    c[yz, 2, 8] = -2.0
    c[xz, 2, 9] = -2.0
    return c / (4.0 * math.pi)


def corner_functions(X: np.ndarray, Y: np.ndarray, z: np.ndarray) -> np.ndarray:
    """The corner functions F0 … F13 of the module docstring at corner
    offsets (X, Y) and depth z > 0 (broadcast): shape (14, ...)."""
    X, Y, z = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (X, Y, z)))
    X2, Y2, z2 = X * X, Y * Y, z * z
    r = np.sqrt(X2 + Y2 + z2)
    rz = r + z
    # X + ρ and Y + ρ without cancellation where X (Y) < 0; > 0 since z > 0
    lx = np.where(X > 0.0, X + r, (Y2 + z2) / (r - np.minimum(X, 0.0)))
    ly = np.where(Y > 0.0, Y + r, (X2 + z2) / (r - np.minimum(Y, 0.0)))
    q = z / (r * rz)
    zx, zy = z / (r * lx), z / (r * ly)
    num = X * Y * (X2 + Y2) / rz  # XY(ρ − z)
    return np.stack([
        np.log(rz), -X / rz, -Y / rz, X * q, Y * q, -z / r,
        np.log(lx), np.log(ly), z * zx, z * zy, Y * zx, X * zy,
        np.arctan2(num, X2 * r + Y2 * z), np.arctan2(num, Y2 * r + X2 * z),
    ])


def _checked_depth(owner: str, name: str, value: object) -> float:
    if isinstance(value, numbers.Real) and not isinstance(value, bool):
        value = float(value)
        if math.isfinite(value) and value > 0.0:
            return value
    raise ConfigError(f"{owner}: {name} must be a finite number > 0 (a depth below the "
                      f"surface, z > 0 inside the body), got {value!r}")


def rectangle_stresses(x: np.ndarray, y: np.ndarray, z: np.ndarray, half_width_x: float,
                       half_width_y: float, poisson_ratio: float) -> np.ndarray:
    """The stresses at (x, y, z), z > 0 (broadcast), per unit uniform traction
    on the rectangle |x'| ≤ a, |y'| ≤ b of the surface (a, b the half-widths):
    shape (..., 6, 3), rows σ_xx, σ_yy, σ_zz, σ_xy, σ_yz, σ_xz (tension
    positive), columns p_x, p_y, p_z (signs in the module docstring)."""
    owner = "rectangle_stresses"
    a = checked_number(owner, "half_width_x", CELL_SIZE, half_width_x)
    b = checked_number(owner, "half_width_y", CELL_SIZE, half_width_y)
    nu = checked_number(owner, "poisson_ratio", POISSON_RATIO, poisson_ratio)
    x, y, z = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (x, y, z)))
    if not (np.all(np.isfinite(x)) and np.all(np.isfinite(y))):
        raise ConfigError(f"{owner}: x and y must be finite")
    if not np.all(z > 0.0) or not np.all(np.isfinite(z)):
        raise ConfigError(f"{owner}: z must be finite and > 0 (inside the body), got "
                          f"min {float(np.min(z, initial=np.inf))!r}")
    F = (corner_functions(x + a, y + b, z) - corner_functions(x - a, y + b, z)
         - corner_functions(x + a, y - b, z) + corner_functions(x - a, y - b, z))
    return np.einsum("clf,f...->...cl", _coefficients(nu), F)


def stress_blocks(nx: int, ny: int, dx: float, dy: float, depth: float,
                  poisson_ratio: float) -> np.ndarray:
    """The 6 × 3 stress blocks of every cell offset on an nx × ny grid of
    cells dx × dy at one depth, shape (2nx − 1, 2ny − 1, 6, 3):
    ``blocks[di + nx − 1, dj + ny − 1]`` is the stress at depth ``depth``
    below the centre of cell (i, j) per unit uniform traction on cell
    (i − di, j − dj) (rows and columns as :func:`rectangle_stresses`).

    The corner functions are evaluated once on the (2nx) × (2ny) lattice of
    corner offsets and differenced: O(nx ny)."""
    nx, ny, dx, dy = checked_grid_size("stress_blocks", nx, ny, dx, dy)
    z = _checked_depth("stress_blocks", "depth", depth)
    nu = checked_number("stress_blocks", "poisson_ratio", POISSON_RATIO, poisson_ratio)
    F = _lattice_integrals(nx, ny, dx, dy, z)
    return np.moveaxis(_combine(_coefficients(nu), F), (0, 1), (2, 3))


def _lattice_integrals(nx: int, ny: int, dx: float, dy: float, z: float) -> np.ndarray:
    """The corner double differences of F0 … F13 for every cell offset:
    (14, 2nx − 1, 2ny − 1), offset (di, dj) at [di + nx − 1, dj + ny − 1]."""
    X = (np.arange(-nx + 1, nx + 1) - 0.5) * dx
    Y = (np.arange(-ny + 1, ny + 1) - 0.5) * dy
    F = corner_functions(X[:, None], Y[None, :], z)
    F = F[:, 1:, :] - F[:, :-1, :]
    return F[:, :, 1:] - F[:, :, :-1]


def _combine(coef: np.ndarray, F: np.ndarray) -> np.ndarray:
    """Σ_f coef[c, l, f] F[f]: (C, L, ...) from (C, L, 14) and (14, ...),
    over the non-zero coefficients only (3–4 of the 14 per entry)."""
    out = np.zeros(coef.shape[:2] + F.shape[1:])
    for (c, l, f) in zip(*np.nonzero(coef)):
        out[c, l] += coef[c, l, f] * F[f]
    return out


class HalfSpaceStress:
    """The stress field inside the half-space z > 0 due to piecewise-constant
    tractions on the cells of a :class:`Grid` (signs and components: module
    docstring).

    Parameters
    ----------
    grid: the cells.
    poisson_ratio: ν of the body, −1 < ν < 0.5 (the stresses of given
        tractions do not depend on the shear modulus).

    Tractions are (n, 3) arrays in the grid's cell order (row I = i ny + j:
    p_x, p_y, p_z of cell (i, j)), in stress units.

    * :meth:`layers` / :meth:`layer`: the stresses below every cell centre at
      given depths, by FFT: the 3 traction components are transformed once
      (zero-padded to 2nx × 2ny) for all depths; per depth the 14 corner
      functions are evaluated on the 2nx × 2ny corner lattice, the 6 × 3 stress
      kernels formed and transformed (one real FFT per kernel whose traction
      component is not identically zero), multiplied and summed, and the 6
      components transformed back: O(n log n) per depth.
    * :meth:`at`: the stresses at arbitrary points, summed over the cells
      directly, O(n) per point: for a few points, off the layers.

    The depth kernels' spectra and the points' corner sums do not depend on
    the tractions: they are kept (up to :data:`KEEP_BYTES`) and reused when
    the same depths or points are asked under other tractions.
    """

    def __init__(self, grid: Grid, poisson_ratio: float) -> None:
        if not isinstance(grid, Grid):
            raise ConfigError(f"HalfSpaceStress: grid must be a Grid, got {type(grid).__name__}")
        self.grid = grid
        self.poisson_ratio = checked_number("HalfSpaceStress", "poisson_ratio", POISSON_RATIO,
                                            poisson_ratio)
        self._coef = _coefficients(self.poisson_ratio)
        self._kept: dict = {}
        self._kept_bytes = 0

    def _keep(self, key, value: np.ndarray) -> np.ndarray:
        if self._kept_bytes + value.nbytes <= KEEP_BYTES:
            self._kept[key] = value
            self._kept_bytes += value.nbytes
        return value

    def _spectra(self, z: float, components: list[int], s: tuple[int, int]) -> list[np.ndarray]:
        """Per traction component, the spectra (6, s0, s1 // 2 + 1) of the
        stress kernels at depth z (zero-padded to ``s``)."""
        missing = [c for c in components if ("layer", z, c) not in self._kept]
        new = {}
        if missing:
            nx, ny = self.grid.shape
            F = _lattice_integrals(nx, ny, self.grid.dx, self.grid.dy, z)
            # kernel of offset (di, dj) at [di + nx − 1, dj + ny − 1], zero-padded by the FFT
            hat = scipy.fft.rfft2(_combine(self._coef[:, missing, :], F), s=s, axes=(2, 3))
            for m, c in enumerate(missing):
                new[c] = self._keep(("layer", z, c), np.ascontiguousarray(hat[:, m]))
        return [new[c] if c in new else self._kept[("layer", z, c)] for c in components]

    def _tractions(self, owner: str, tractions: object) -> np.ndarray:
        t = np.asarray(tractions, dtype=float)
        n = self.grid.size
        if t.shape != (n, 3):
            raise ConfigError(f"HalfSpaceStress.{owner}: tractions must have shape (n, 3) with "
                              f"n = {n} cells, got {t.shape}")
        if not np.all(np.isfinite(t)):
            raise ConfigError(f"HalfSpaceStress.{owner}: tractions must be finite")
        return t

    def layers(self, tractions: np.ndarray, depths: np.ndarray) -> np.ndarray:
        """The stresses below the cell centres at each depth: shape
        (len(depths), nx, ny, 6) (``[k].reshape(n, 6)`` is in cell order).
        ``depths``: a sequence of depths > 0 (length units)."""
        t = self._tractions("layers", tractions)
        d = np.asarray(depths, dtype=float)
        if d.ndim != 1 or not np.all(np.isfinite(d)) or not np.all(d > 0.0):
            raise ConfigError(f"HalfSpaceStress.layers: depths must be a 1-D sequence of finite "
                              f"depths > 0 (z > 0 inside the body), got {depths!r}")
        nx, ny = self.grid.shape
        s = (2 * nx, 2 * ny)
        loaded = [c for c in range(3) if np.any(t[:, c] != 0.0)]
        spectra = {c: scipy.fft.rfft2(t[:, c].reshape(nx, ny), s=s) for c in loaded}
        out = np.zeros((d.size, nx, ny, 6))
        if not loaded:
            return out
        for k, z in enumerate(d):
            # the circular product holds cell (i, j) at [i + nx − 1, j + ny − 1]
            hat = self._spectra(float(z), loaded, s)
            total = hat[0] * spectra[loaded[0]]
            for m, c in enumerate(loaded[1:], start=1):
                total += hat[m] * spectra[c]
            field = scipy.fft.irfft2(total, s=s, axes=(1, 2))
            out[k] = np.moveaxis(field[:, nx - 1: 2 * nx - 1, ny - 1: 2 * ny - 1], 0, -1)
        return out

    def layer(self, tractions: np.ndarray, depth: float) -> np.ndarray:
        """The stresses below the cell centres at one depth > 0: shape
        (nx, ny, 6)."""
        z = _checked_depth("HalfSpaceStress.layer", "depth", depth)
        return self.layers(tractions, [z])[0]

    def at(self, points: np.ndarray, tractions: np.ndarray) -> np.ndarray:
        """The stresses at ``points`` (m, 3) = (x, y, depth), depth > 0:
        shape (m, 6).  Direct sum over the cells, 14 (nx + 1)(ny + 1)
        corner-function values per point."""
        t = self._tractions("at", tractions)
        p = np.asarray(points, dtype=float)
        if p.ndim != 2 or p.shape[1] != 3:
            raise ConfigError(f"HalfSpaceStress.at: points must have shape (m, 3) = (x, y, "
                              f"depth), got {p.shape}")
        if not np.all(np.isfinite(p)):
            raise ConfigError("HalfSpaceStress.at: points must be finite")
        if not np.all(p[:, 2] > 0.0):
            raise ConfigError(f"HalfSpaceStress.at: points must lie inside the body, depth "
                              f"z > 0, got min z = {float(p[:, 2].min())!r}")
        g = self.grid
        nx, ny = g.shape
        # W[c, f, i, j]: the traction of cell (i, j) weighted for component c, function f
        W = np.einsum("clf,ijl->cfij", self._coef, t.reshape(nx, ny, 3))
        xc = g.origin[0] + np.arange(nx + 1) * g.dx
        yc = g.origin[1] + np.arange(ny + 1) * g.dy
        out = np.empty((p.shape[0], 6))
        step = max(1, _CHUNK_VALUES // (_NF * (nx + 1) * (ny + 1)))
        for start in range(0, p.shape[0], step):
            q = p[start:start + step]
            key = ("at", q.tobytes())
            cells = self._kept.get(key)
            if cells is None:
                F = corner_functions((q[:, 0, None] - xc)[:, :, None],
                                     (q[:, 1, None] - yc)[:, None, :], q[:, 2, None, None])
                # a cell [x_i, x_i+1] × [y_j, y_j+1]: offsets X = x − x_i > X' = x − x_i+1
                cells = self._keep(key, F[:, :, :-1, :-1] - F[:, :, 1:, :-1] - F[:, :, :-1, 1:]
                                   + F[:, :, 1:, 1:])
            out[start:start + step] = np.einsum("fmij,cfij->mc", cells, W)
        return out
