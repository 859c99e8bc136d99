"""The pair's operator on the grid (multiscale/operator.py): the generic
block-Toeplitz product against the half-space operator it generalizes, the
corrections added, and the preconditioner's symbol."""

from __future__ import annotations

import numpy as np

from bemcontact.halfspace import Compliance, Grid, HalfSpaceOperator
from bemcontact.multiscale.operator import PairOperator, ToeplitzOperator

PAIR = Compliance.pair(30.0, 0.1, 70.0, 0.45)  # dissimilar: the coupling K is not zero


def test_toeplitz_product_equals_the_half_space_product():
    """ToeplitzOperator from the half-space blocks (9 kernels, no symmetry
    used) equals HalfSpaceOperator's product (6 kernels) to 1e-14 of the
    result on a non-square grid."""
    grid = Grid.centred(7, 5, 0.3, 0.2)
    hs = HalfSpaceOperator(grid, PAIR)
    t = np.random.default_rng(1).standard_normal((grid.size, 3))
    a, b = ToeplitzOperator(grid, hs.blocks).matvec(t), hs.matvec(t)
    assert np.abs(a - b).max() < 1e-14 * np.abs(b).max()


def test_corrections_add_and_the_preconditioner_inverts_the_symbol():
    """C t = C_hs t + Σ ΔC t.  The preconditioner's per-mode blocks are
    Hermitian positive definite, and the inverse of the padded kernel's
    symbol on every mode where that symbol is positive definite (the
    truncated kernel's symbol is indefinite on a few modes: measured 1 of
    the 60 on this grid; there the eigenvalues' magnitudes are inverted)."""
    grid = Grid.centred(6, 4, 0.25, 0.25)

    class Shift:
        def matvec(self, t):
            return 2.0 * t

    op = PairOperator(grid, PAIR, [Shift()])
    t = np.random.default_rng(2).standard_normal((grid.size, 3))
    assert np.allclose(op.matvec(t), op.halfspace_matvec(t) + 2.0 * t, rtol=0, atol=1e-14)
    kxx, kyy, kzz, kxy, kxz, kyz = op.halfspace._kernels
    sym = np.empty(kxx.shape + (3, 3), dtype=complex)
    sym[..., 0, :] = np.stack([kxx, kxy, kxz], axis=-1)
    sym[..., 1, :] = np.stack([kxy, kyy, kyz], axis=-1)
    sym[..., 2, :] = np.stack([-kxz, -kyz, kzz], axis=-1)
    inv = op._inverse
    assert np.allclose(inv, np.conj(np.swapaxes(inv, -1, -2)), rtol=0, atol=1e-12 * np.abs(inv).max())
    assert np.linalg.eigvalsh(inv).min() > 0.0
    definite = np.linalg.eigvalsh(0.5 * (sym + np.conj(np.swapaxes(sym, -1, -2)))).min(axis=-1) > 0
    assert definite.mean() > 0.9
    prod = np.einsum("...ij,...jk->...ik", inv[definite], sym[definite])
    assert np.abs(prod - np.eye(3)).max() < 1e-10
