"""The frame's relative displacement as an affine map of the interface
unknowns, and the linear rows besides the contact law: what the condensed
bodies' flexibilities (:class:`~bemcontact.contact.flexibility.Flexibility`)
give the interface system.

    k = k0X + k0u ell + K lam + sum_i L_i v_i       (3m, local components)

with lam the frame tractions, v_i the extra unknowns (per body its free
rigid-mode amplitudes alpha, then its platen translations U) and ell the load
weights; E_a lam (+ the modal loads) the equilibrium of body a's free modes,
CT_a lam + CY_a U_a the resultants of its force-controlled components."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse
import scipy.sparse.linalg

from ..errors import ConfigError
from .frame import ContactFrame
from .modes import CHUNK

#: Entries of a rigid mode's or platen translation's column of dk/dz (and of
#: its equilibrium row) below this fraction of the column's (row's) largest
#: are round-off of an exact zero (docs/theory.md, "Verified solutions").
ROUNDOFF = 1e-11


def drop_roundoff(M: np.ndarray, axis: int = 0) -> np.ndarray:
    """``M`` with the entries below :data:`ROUNDOFF` of the largest of their
    column (``axis`` 0) or row (``axis`` 1) set to exactly zero, in place.

    A rigid mode that moves a frictionless body in the contact's plane (a
    slide, a turn about the normal) changes no normal gap in exact
    arithmetic; computed, its normal components are round-off of the frame
    normals (1e-17 of its tangential ones).  Left in, they would make the
    start of a solve and the singular diagnosis depend on the processor: a
    penalty balance on those components can move a free cube by 2e15 mm,
    open every node and leave a residual of exactly zero.  Zeroed, such a
    mode moves no gap, the Newton matrix has an exactly zero column for it
    and the LU's zero pivot reports the singular matrix on every machine."""
    if M.size:
        big = np.abs(M).max(axis=axis, keepdims=True)
        M[np.abs(M) <= ROUNDOFF * big] = 0.0
    return M


class RelativeDisplacement:
    """The relative displacement k (3m, local components) from the nodal
    forces' work rows g = Bᵀ x (∫ N_j [u] per frame node, local
    components): ``weighted``, k_j = g_j / a_j; ``projected``, k = Qᵀ (M_f^-1
    ⊗ I_3) Q g, the nodal values of the L2 projection on the frame basis
    (rotated to global components first: the nodes' bases differ on a
    curved frame), with the weighted row at the nodes whose support the
    other body covers only in part (:attr:`ContactFrame.covered`).  Called
    on (3m,) or (3m, r) arrays, projected in blocks of
    :data:`~bemcontact.contact.modes.CHUNK` columns: with ``overwrite``
    in place (no copy of a (3m)² block)."""

    def __init__(self, frame: ContactFrame, act: np.ndarray) -> None:
        self.m = act.size
        a = frame.weights[act]
        self.a3 = np.repeat(a, 3)
        self.lu = None
        if frame.projected and self.m:
            self.Q = frame.Q[act]
            self.Qt = np.ascontiguousarray(self.Q.transpose(0, 2, 1))
            # a node whose support the other body covers only in part (the rim
            # of a punch on a larger block: slivers down to 1e-10 of it), and
            # its neighbours, keep the weighted row a_j k_j = g_j: the
            # projection's value there rests on a sliver (M_f as ill-conditioned
            # as the slivers are thin), M_f^-1 would carry that noise inward,
            # and the rim nodes' late state changes would reach their
            # neighbours' gaps (the punch: 26 Newton iterations, 14 with the
            # ring weighted)
            edge = ~frame.covered[act]
            keep = scipy.sparse.diags((~edge).astype(float))
            M = keep @ scipy.sparse.csr_array(frame.mass[np.ix_(act, act)]) + scipy.sparse.diags(
                np.where(edge, a, 0.0))
            self.lu = scipy.sparse.linalg.splu(scipy.sparse.csc_array(M))

    def _project(self, G: np.ndarray) -> np.ndarray:
        m, r = self.m, G.shape[1]
        g = np.matmul(self.Q, G.reshape(m, 3, r))  # global components
        g = self.lu.solve(np.asfortranarray(g.reshape(m, 3 * r))).reshape(m, 3, r)
        # back to local (matmul: einsum's contraction over the first index
        # took 0.57 s on a 3,395 x 3 x 2,048 block, measured)
        return np.matmul(self.Qt, g).reshape(3 * m, r)

    def __call__(self, G, overwrite: bool = False) -> np.ndarray:
        """W G; a (3m, r) ``G`` is overwritten only with ``overwrite``."""
        G = np.asarray(G, dtype=float)
        if self.lu is None:
            return G / (self.a3 if G.ndim == 1 else self.a3[:, None])
        if G.ndim == 1:
            return self._project(G[:, None])[:, 0]
        if not (overwrite and G.flags.writeable):
            G = G.copy()
        for s in range(0, G.shape[1], CHUNK):
            G[:, s : s + CHUNK] = self._project(G[:, s : s + CHUNK])
        return G


@dataclass
class Kinematics:
    """The affine map to k and the linear rows (see the module docstring):
    ``K`` (3m, 3m), ``k0X`` (3m,) the initial positions' part, ``k0u``
    (3m, S) the load states', ``L`` the extra unknowns' columns (per body
    alpha's then U's), ``E`` per body (nf, 3m), ``CT`` per body (nc, 3m),
    ``CY`` per body (nc, nc), ``nf`` and ``nc`` per body."""

    K: np.ndarray
    k0X: np.ndarray
    k0u: np.ndarray
    L: list
    E: list
    CT: list
    CY: list
    nf: list
    nc: list

    @classmethod
    def assemble(cls, fs, cb) -> Kinematics:
        """From the frames ``fs`` (a :class:`~bemcontact.contact.frames.FrameSet`)
        and each body's flexibility ``cb`` (in the FrameSet's body order),
        condensed on the frames' traction modes."""
        m = fs.m
        npairs = len(fs.frames)
        weighs = [RelativeDisplacement(f, act) for f, act in zip(fs.frames, fs.act)]

        def weigh(G, p, overwrite=False):
            return weighs[p](G, overwrite=overwrite)

        K = np.zeros((3 * m, 3 * m))
        k0X = np.zeros(3 * m)
        k0u = np.zeros((3 * m, cb[0].u0.shape[1]))
        # extra unknowns: per body, alpha then U; L[b] their columns in k
        nf = [c.Rc.shape[1] for c in cb]
        nc = [c.Yc.shape[1] for c in cb]
        L = []
        E = []
        CT = []  # (nc, 3m): resultants of the controlled components per lam
        CY = []  # (nc, nc): ... per platen translation
        for i, c in enumerate(cb):
            if c.modes is None or c.modes.size != 3 * m:
                raise ConfigError(
                    f"{c.name}: condense the body on the frame's traction modes "
                    "(condense(..., modes=traction_modes(frame)[i]))"
                )
            # nodal forces per frame traction B (signed); the relative
            # displacement k = sum_a W_a x_a[dofs], W_a = weigh(B_a^T),
            # on the rows of the pairs the body is in
            Bt = c.modes.B.T.tocsr()  # (3m, 3n) sparse
            Rc, Yc = c.Rc, c.Yc
            Li = np.zeros((3 * m, Rc.shape[1]))
            Ly = np.zeros((3 * m, Yc.shape[1]))
            for p, side in fs.pairs_of(i):
                f, dp = fs.frames[p], fs.dofs(p)
                Bp = Bt[dp]
                # the work rows B^T F, weighed once per pair below (weigh is
                # linear: one projection of the sum instead of one per body;
                # F = X[dofs] gathered first: a sparse product with the
                # Fortran-ordered X itself took 1.7x longer, measured)
                K[dp] += Bp @ c.F
                if f.rule == "mortar":
                    # positions: exact for any overlap because (*) holds
                    X = c.points.ravel()
                else:
                    # point evaluation violates (*): take the initial gap from each
                    # node's offset to the frame surface (the paper's g0), so the
                    # position of the origin does not enter
                    X = np.zeros((c.points.shape[0], 3))
                    X[fs.rows(p, side)] = f.offsets(side)
                    X = X.ravel()
                k0X[dp] += weigh(Bp @ X, p)
                k0u[dp] += weigh(Bp @ c.u0, p)
                Li[dp] = weigh(Bp @ Rc, p)
                Ly[dp] = weigh(Bp @ Yc, p)
            L.append(drop_roundoff(Li))
            L.append(drop_roundoff(Ly))
            # equilibrium in the free rigid modes, scaled to traction units
            E.append(drop_roundoff(np.asarray((Bt @ Rc).T), axis=1))
            CT.append(drop_roundoff(np.asarray(c.CX), axis=1))
            CY.append(c.CY)
        for p in range(npairs):
            dp = fs.dofs(p)
            w = weigh(K[dp], p, overwrite=True)  # in place when projected
            if not np.shares_memory(w, K):
                K[dp] = w
        return cls(K, k0X, k0u, L, E, CT, CY, nf, nc)

    def extra_columns(self) -> np.ndarray:
        """dk/d(extra unknowns): the columns of L side by side (3m, ne)."""
        m3 = self.K.shape[0]
        return np.hstack([L for L in self.L]) if self.L else np.zeros((m3, 0))

    def linear_rows(self, area: float) -> np.ndarray:
        """The rows besides the law over z = (lam, extras), in traction
        units (divided by the frame's ``area``): per body its free modes'
        equilibrium, then its controlled resultants."""
        m3 = self.K.shape[0]
        nz = m3 + sum(self.nf) + sum(self.nc)
        eq = []
        col = m3
        for i in range(len(self.nf)):
            nf, nc = self.nf[i], self.nc[i]
            if nf:
                r = np.zeros((nf, nz))
                r[:, :m3] = self.E[i] / area
                eq.append(r)
            if nc:
                r = np.zeros((nc, nz))
                r[:, :m3] = self.CT[i] / area
                r[:, col + nf : col + nf + nc] = self.CY[i] / area
                eq.append(r)
            col += nf + nc
        return np.vstack(eq) if eq else np.zeros((0, nz))

    def restricted(self, P, R) -> Kinematics:
        """The same map on clusters of frame nodes: K_c = R K P, the affine
        terms and the extra unknowns' columns restricted by R, the
        equilibrium and resultant rows taken on P lam_c."""
        RK = R @ self.K  # (3mc, 3m): K is C-ordered, read once
        K = np.ascontiguousarray((P.T @ RK.T).T)
        del RK
        return Kinematics(
            K, R @ self.k0X, R @ self.k0u, [R @ L for L in self.L],
            [np.asarray((P.T @ E.T).T) for E in self.E],
            [np.asarray((P.T @ CT.T).T) for CT in self.CT], self.CY, self.nf, self.nc)


__all__ = ["Kinematics", "RelativeDisplacement", "ROUNDOFF", "drop_roundoff"]
