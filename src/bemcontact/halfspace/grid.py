"""A regular grid of rectangular cells in the plane z = 0 and the half-space
operator on it, applied by FFT.

Cells are numbered in C order of (nx, ny): cell (i, j), its centre at
``origin + ((i + ½) dx, (j + ½) dy)``, is cell ``I = i ny + j``.  A traction or
displacement field is an (n, 3) array, row I = (x, y, z) components of cell I,
or the same flattened to (3n,): dof ``3 I + c``.  Signs: :mod:`.influence`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.fft
from scipy.sparse.linalg import LinearOperator

from ..errors import ConfigError
from .influence import Compliance, checked_grid_size, influence_blocks

#: The six independent entries of a block (the others: C_yx = C_xy,
#: C_zx = −C_xz, C_zy = −C_yz), as (row, column).
INDEPENDENT = ((0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2))


@dataclass(frozen=True)
class Grid:
    """nx × ny cells of size dx × dy (length units); ``origin`` (x, y) is the
    corner of cell (0, 0) with the smallest coordinates."""

    origin: tuple[float, float]
    nx: int
    ny: int
    dx: float
    dy: float

    def __post_init__(self) -> None:
        nx, ny, dx, dy = checked_grid_size("Grid", self.nx, self.ny, self.dx, self.dy)
        try:
            origin = tuple(float(v) for v in np.asarray(self.origin, dtype=float).reshape(-1))
        except (TypeError, ValueError):
            raise ConfigError(f"Grid: origin must be two numbers (x, y), got {self.origin!r}")
        if len(origin) != 2 or not all(math.isfinite(v) for v in origin):
            raise ConfigError(f"Grid: origin must be two finite numbers (x, y), got "
                              f"{self.origin!r}")
        for name, value in (("origin", origin), ("nx", nx), ("ny", ny), ("dx", dx), ("dy", dy)):
            object.__setattr__(self, name, value)

    @classmethod
    def centred(cls, nx: int, ny: int, dx: float, dy: float,
                centre: tuple[float, float] = (0.0, 0.0)) -> Grid:
        """The grid whose centre is ``centre`` (with odd nx and ny, the centre
        of the middle cell)."""
        return cls((centre[0] - 0.5 * nx * dx, centre[1] - 0.5 * ny * dy), nx, ny, dx, dy)

    @property
    def shape(self) -> tuple[int, int]:
        return (self.nx, self.ny)

    @property
    def size(self) -> int:
        """The number of cells n = nx ny."""
        return self.nx * self.ny

    @property
    def cell_area(self) -> float:
        return self.dx * self.dy

    @property
    def centres(self) -> np.ndarray:
        """The cell centres, (n, 3) float64 C-contiguous (z = 0), in cell order."""
        x = self.origin[0] + (np.arange(self.nx) + 0.5) * self.dx
        y = self.origin[1] + (np.arange(self.ny) + 0.5) * self.dy
        out = np.zeros((self.nx, self.ny, 3))
        out[..., 0] = x[:, None]
        out[..., 1] = y[None, :]
        return out.reshape(-1, 3)


class HalfSpaceOperator:
    """The half-space influence operator of piecewise-constant tractions on a
    :class:`Grid`: displacement at the cell centres = C · traction.

    C is block Toeplitz, so it is stored as the FFTs of its six independent
    kernels on the zero-padded (2nx) × (2ny) grid (6 (2nx)(ny + 1) complex
    numbers); a product is 3 forward real FFTs, 9 pointwise products and 3
    inverse FFTs, O(n log n).  C is symmetric (reciprocity).

    Parameters
    ----------
    grid: the cells.
    compliance: the material: ``Compliance.half_space(G, ν)`` for one body,
        ``Compliance.pair(G_1, ν_1, G_2, ν_2)`` for the relative displacement
        u_2 − u_1 of two (signs: :mod:`bemcontact.halfspace.influence`).
    """

    def __init__(self, grid: Grid, compliance: Compliance) -> None:
        if not isinstance(grid, Grid):
            raise ConfigError(f"HalfSpaceOperator: grid must be a Grid, got {type(grid).__name__}")
        if not isinstance(compliance, Compliance):
            raise ConfigError(f"HalfSpaceOperator: compliance must be a Compliance, got "
                              f"{type(compliance).__name__}")
        self.grid = grid
        self.compliance = compliance
        nx, ny = grid.shape
        #: blocks[i − j + nx − 1, k − l + ny − 1]: see :func:`influence_blocks`.
        self.blocks = influence_blocks(nx, ny, grid.dx, grid.dy, compliance)
        # offset (di, dj) at index (di mod 2nx, dj mod 2ny); the row and column
        # of offset ±nx (±ny) stay zero (no pair of cells is that far apart)
        padded = np.zeros((6, 2 * nx, 2 * ny))
        for k, (a, b) in enumerate(INDEPENDENT):
            padded[k, : 2 * nx - 1, : 2 * ny - 1] = self.blocks[..., a, b]
        padded = np.roll(padded, (-(nx - 1), -(ny - 1)), axis=(1, 2))
        self._kernels = scipy.fft.rfft2(padded, axes=(1, 2))

    @property
    def shape(self) -> tuple[int, int]:
        """(3n, 3n)."""
        return (3 * self.grid.size, 3 * self.grid.size)

    def matvec(self, traction: np.ndarray) -> np.ndarray:
        """The displacements at the cell centres due to ``traction``.

        ``traction`` is (n, 3) (one field, per cell), (..., n, 3) (several),
        (3n,) (one flattened field) or (3n, k) (k flattened fields as
        columns); the result has the same shape."""
        t = np.asarray(traction, dtype=float)
        n = self.grid.size
        nx, ny = self.grid.shape
        if t.ndim >= 2 and t.shape[-2:] == (n, 3):
            fields = t.reshape(-1, nx, ny, 3)
            out = self._apply(np.moveaxis(fields, -1, 1))
            return np.moveaxis(out, 1, -1).reshape(t.shape)
        if t.ndim in (1, 2) and t.shape[0] == 3 * n:
            columns = t.reshape(nx, ny, 3, -1)
            out = self._apply(np.transpose(columns, (3, 2, 0, 1)))
            return np.transpose(out, (2, 3, 1, 0)).reshape(t.shape)
        raise ConfigError(
            f"HalfSpaceOperator.matvec: traction must have shape (n, 3), (..., n, 3), (3n,) or "
            f"(3n, k) with n = {n} cells, got {t.shape}")

    def _apply(self, t: np.ndarray) -> np.ndarray:
        """(m, 3, nx, ny) tractions -> (m, 3, nx, ny) displacements."""
        nx, ny = self.grid.shape
        s = (2 * nx, 2 * ny)
        tx, ty, tz = (scipy.fft.rfft2(t[:, c], s=s, axes=(1, 2)) for c in range(3))
        kxx, kyy, kzz, kxy, kxz, kyz = self._kernels
        u = np.stack([kxx * tx + kxy * ty + kxz * tz,
                      kxy * tx + kyy * ty + kyz * tz,
                      kzz * tz - kxz * tx - kyz * ty], axis=1)
        return scipy.fft.irfft2(u, s=s, axes=(2, 3))[..., :nx, :ny]

    def __matmul__(self, traction: np.ndarray) -> np.ndarray:
        return self.matvec(traction)

    def as_linear_operator(self) -> LinearOperator:
        """C as a SciPy ``LinearOperator`` on flattened fields (3n,) and
        (3n, k); C is symmetric, so its transpose is itself."""
        return LinearOperator(self.shape, matvec=self.matvec, rmatvec=self.matvec,
                              matmat=self.matvec, rmatmat=self.matvec, dtype=np.float64)

    def dense(self) -> np.ndarray:
        """C formed, (3n, 3n) float64 (dof 3 I + c): for small grids and tests
        (8 · 9 n² bytes, twice while forming)."""
        nx, ny = self.grid.shape
        i, j = np.divmod(np.arange(self.grid.size), ny)
        di = i[:, None] - i[None, :] + nx - 1
        dj = j[:, None] - j[None, :] + ny - 1
        n = self.grid.size
        return np.ascontiguousarray(self.blocks[di, dj].transpose(0, 2, 1, 3).reshape(3 * n, 3 * n))
