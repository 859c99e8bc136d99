"""Traction modes: the tractions a unit frame traction puts on a body.

The frame tractions lam (3 m, the active frame nodes' local components) act
on body a through its localized multipliers, the nodal forces
f_a = s_a B_a lam with B_a = (D_a ⊗ I_3) Q (sparse: a node couples to the
few frame nodes its support overlaps; s_1 = -1, s_2 = +1), and its contact
tractions are t_a = (M_a^-1 ⊗ I_3) f_a = T_a lam with the consistent mass
M_a (docs/frame.md).  The body is condensed on the 3 m columns of T_a (its
response to each frame traction component), not on its 3 n_a contact dofs:
fewer right-hand sides whenever the frame is the coarser surface, and the
interface flexibility W_a F_a T_a becomes a sparse product.  T_a itself is
not formed (M_a^-1 is not local): it is applied through a sparse factor of
M_a.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg
import scipy.sparse
import scipy.sparse.linalg

#: Rows of a right factor processed at once by :meth:`TractionModes.right`
#: (bounds its temporary memory to a few such blocks).
CHUNK = 2048
#: Largest contact surface (nodes) whose mass :meth:`TractionModes.right`
#: inverts densely: a dense Cholesky solve with many right-hand sides runs
#: at BLAS-3 speed, 3.5x faster than SuperLU's sparse one at 1,197 nodes
#: (1.07 s against 3.73 s for 15,777 right-hand sides, measured), and a
#: product with the dense inverse twice as fast again; above this the n^2
#: memory decides (288 MB).
DENSE_MASS = 6000


class TractionModes:
    """T_a = s_a (M_a^-1 ⊗ I_3) (D_a ⊗ I_3) Q for body a, with ``D`` (n, m)
    the coupling to the active frame nodes (sparse), ``Q`` (m, 3, 3) their
    local bases, ``M`` (n, n) the sparse consistent mass and ``sign`` s_a.

    ``B`` is s_a (D ⊗ I_3) Q as a sparse (3n, 3m) array (the nodal forces per
    unit frame traction); ``size`` = 3m is the number of modes."""

    def __init__(self, D, Q: np.ndarray, M, sign: float) -> None:
        D = scipy.sparse.coo_array(D)
        n, m = D.shape
        self.n, self.m = n, m
        # block (p, j) = D[p, j] Q_j: entries (3p + c, 3j + l) = D[p, j] Q_j[c, l]
        c, l_ = np.meshgrid(np.arange(3), np.arange(3), indexing="ij")
        rows = 3 * D.row[:, None, None] + c[None]
        cols = 3 * D.col[:, None, None] + l_[None]
        vals = sign * D.data[:, None, None] * Q[D.col]
        self.B = scipy.sparse.coo_array(
            (vals.ravel(), (rows.ravel(), cols.ravel())), shape=(3 * n, 3 * m)
        ).tocsr()
        self.size = 3 * m
        self._M = scipy.sparse.csc_array(M)
        self._lu = scipy.sparse.linalg.splu(self._M)

    def _minv(self, F: np.ndarray) -> np.ndarray:
        """(M^-1 ⊗ I_3) F for F (3n, r)."""
        r = F.shape[1]
        G = F.reshape(self.n, 3 * r)
        return self._lu.solve(np.asfortranarray(G)).reshape(3 * self.n, r)

    def tractions(self, lam: np.ndarray) -> np.ndarray:
        """T lam: the contact tractions (3n,) (or (3n, r) for lam (3m, r))."""
        f = self.B @ lam
        return self._minv(f.reshape(3 * self.n, -1)).reshape(f.shape)

    def right(self, G: np.ndarray, out: np.ndarray | None = None) -> np.ndarray:
        """G T for G (r, 3n): each row of G, a functional of the contact
        tractions, as a functional of the frame tractions (r, 3m).  M is
        symmetric, so G (M^-1 ⊗ I) = ((M^-1 ⊗ I) G^T)^T; rows in blocks of
        :data:`CHUNK`, M factored densely up to :data:`DENSE_MASS` nodes;
        written into ``out`` (r, 3m) if given."""
        if out is None:
            out = np.empty((G.shape[0], self.size))
        minv = self._minv
        if self.n <= DENSE_MASS:
            # M^-1 itself (M is SPD and well conditioned), applied by GEMM:
            # twice the speed of cho_solve's triangular solves on the same
            # block, and its C-ordered result reshapes without a copy
            # (Cattaneo-Mindlin a/h = 25, both bodies: 31 -> about 20 s)
            chol = scipy.linalg.cho_factor(self._M.toarray())
            inverse = scipy.linalg.cho_solve(chol, np.eye(self.n))
            del chol

            def minv(F):
                r = F.shape[1]
                return (inverse @ F.reshape(self.n, 3 * r)).reshape(3 * self.n, r)

        for s in range(0, G.shape[0], CHUNK):
            g = np.ascontiguousarray(G[s : s + CHUNK].T)  # (3n, r)
            out[s : s + CHUNK] = (self.B.T @ minv(g)).T
        return out


__all__ = ["TractionModes"]
