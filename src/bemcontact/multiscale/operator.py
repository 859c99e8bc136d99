"""The flexibility of a pair of bodies on the contact grid: the half-space
(Boussinesq–Cerruti) operator of the pair, applied by FFT, plus each body's
smooth correction for its finite geometry (low rank, :mod:`.correction`),
and an approximate inverse of the half-space part (the preconditioner of the
interface solve).

Fields are (n, 3) arrays over the grid's cells in global (x, y, z)
components; signs as :mod:`bemcontact.halfspace.influence`: the traction
acts on body 2 (z > 0 side), the result is u_2 − u_1 (k_z > 0 opens)."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import scipy.fft

from ..errors import ConfigError
from ..halfspace import Compliance, Grid, HalfSpaceOperator


class PairOperator:
    """k = C t: the relative displacement at the cell centres of the grid
    per traction ``t`` on body 2, C = C_hs + Σ ΔC_a.

    ``corrections``: objects with ``matvec((n, 3)) -> (n, 3)`` giving the
    correction of the relative displacement (each body's, signs included:
    :class:`~.correction.LowRankCorrection`).

    :meth:`precondition` applies the inverse of the circulant that the
    zero-padded half-space kernel defines on the (2nx) × (2ny) torus, per
    Fourier mode a 3 × 3 Hermitian block: restricted to the closed cells it
    is the approximate inverse of the closed cells' block of C (the
    circulant preconditioner of CONTACT's normal solver, here for all three
    components, Dundurs coupling included)."""

    def __init__(self, grid: Grid, compliance: Compliance,
                 corrections: Sequence = ()) -> None:
        self.grid = grid
        self.compliance = compliance
        self.halfspace = HalfSpaceOperator(grid, compliance)
        self.corrections = list(corrections)
        # corrections with a block-Toeplitz part (a curved face's near field,
        # ``near_blocks``) join the half-space kernels in one FFT product and
        # add their ``low_rank`` part; the others add their ``matvec``
        near = [c.near_blocks for c in self.corrections
                if getattr(c, "near_blocks", None) is not None]
        self._toeplitz = (ToeplitzOperator(grid, self.halfspace.blocks + sum(near))
                          if near else None)
        nx, ny = grid.shape
        #: (3, 3) the half-space block of a cell on itself
        self.self_block = self.halfspace.blocks[nx - 1, ny - 1].copy()
        kxx, kyy, kzz, kxy, kxz, kyz = self.halfspace._kernels
        sym = np.empty(kxx.shape + (3, 3), dtype=complex)
        sym[..., 0, 0], sym[..., 1, 1], sym[..., 2, 2] = kxx, kyy, kzz
        sym[..., 0, 1] = sym[..., 1, 0] = kxy
        sym[..., 0, 2], sym[..., 1, 2] = kxz, kyz
        sym[..., 2, 0], sym[..., 2, 1] = -kxz, -kyz
        # the padded kernel's symbol is Hermitian positive definite on
        # every mode (the 1/r kernel's); a mode where it is not (truncation
        # of the kernel at the grid's size) gets its eigenvalues' magnitudes
        w, v = np.linalg.eigh(0.5 * (sym + np.conj(np.swapaxes(sym, -1, -2))))
        if not np.all(np.isfinite(w)) or w.max() <= 0.0:
            raise ConfigError("PairOperator: the half-space symbol is not positive")
        w = np.maximum(np.abs(w), 1e-12 * w.max())
        self._inverse = np.einsum("...ij,...j,...kj->...ik", v, 1.0 / w, np.conj(v))
        self._inverse_modes = np.ascontiguousarray(np.moveaxis(self._inverse, (2, 3), (0, 1)))

    @property
    def n(self) -> int:
        return self.grid.size

    def matvec(self, t: np.ndarray) -> np.ndarray:
        """(n, 3) -> (n, 3): C t."""
        if self._toeplitz is None:
            u = self.halfspace.matvec(t)
            for c in self.corrections:
                u = u + c.matvec(t)
            return u
        u = self._toeplitz.matvec(t)
        for c in self.corrections:
            u = u + (c.low_rank(t) if getattr(c, "near_blocks", None) is not None
                     else c.matvec(t))
        return u

    def halfspace_matvec(self, t: np.ndarray) -> np.ndarray:
        """(n, 3) -> (n, 3): C_hs t alone (the correction switched off)."""
        return self.halfspace.matvec(t)

    def precondition(self, u: np.ndarray) -> np.ndarray:
        """(n, 3) -> (n, 3): the circulant approximate inverse of C_hs."""
        return padded_product(self.grid, self._inverse_modes, u)


def padded_product(grid: Grid, modes: np.ndarray, u: np.ndarray) -> np.ndarray:
    """(n, 3) -> (n, 3): the field ``u`` on ``grid``, zero-padded to the
    (2nx) × (2ny) torus, multiplied per Fourier mode by the 3 × 3 blocks
    ``modes`` (3, 3, 2nx, ny + 1) and cropped back to the grid."""
    nx, ny = grid.shape
    s = (2 * nx, 2 * ny)
    f = scipy.fft.rfft2(np.moveaxis(u.reshape(nx, ny, 3), -1, 0), s=s, axes=(1, 2))
    g = np.einsum("ijxy,jxy->ixy", modes, f)
    out = scipy.fft.irfft2(g, s=s, axes=(1, 2))[:, :nx, :ny]
    return np.moveaxis(out, 0, -1).reshape(-1, 3)


class ToeplitzOperator:
    """A block-Toeplitz operator on a grid's cells from its blocks,
    ``blocks[i − j + nx − 1, k − l + ny − 1]`` (3, 3) the response at cell
    (i, k) to a unit traction on cell (j, l), applied by FFT on the
    zero-padded grid (9 kernels: no symmetry assumed)."""

    def __init__(self, grid: Grid, blocks: np.ndarray) -> None:
        nx, ny = grid.shape
        if blocks.shape != (2 * nx - 1, 2 * ny - 1, 3, 3):
            raise ConfigError(f"ToeplitzOperator: blocks must have shape "
                              f"{(2 * nx - 1, 2 * ny - 1, 3, 3)}, got {blocks.shape}")
        self.grid = grid
        padded = np.zeros((3, 3, 2 * nx, 2 * ny))
        padded[:, :, : 2 * nx - 1, : 2 * ny - 1] = np.moveaxis(blocks, (2, 3), (0, 1))
        padded = np.roll(padded, (-(nx - 1), -(ny - 1)), axis=(2, 3))
        self._kernels = scipy.fft.rfft2(padded, axes=(2, 3))

    def matvec(self, t: np.ndarray) -> np.ndarray:
        """(n, 3) -> (n, 3)."""
        return padded_product(self.grid, self._kernels, t)


__all__ = ["PairOperator", "ToeplitzOperator", "padded_product"]
