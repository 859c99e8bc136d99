"""The interface system of eq. 17 after condensing the bodies: unknowns,
the affine map to the frame's relative displacements k, the residual of the
contact law and the other linear rows, the generalized Jacobian and the
first-touch predictor.  Solved by :mod:`bemcontact.contact.newton`; results
recovered by :mod:`bemcontact.contact.recovery`."""

from __future__ import annotations


import numpy as np
import scipy.sparse
import scipy.sparse.linalg

from ..errors import ConfigError
from . import law
from .frame import ContactFrame
from .frames import FrameSet
from .modes import CHUNK, TractionModes
from .touch import first_touch


def traction_modes(frame: ContactFrame | FrameSet) -> tuple[TractionModes, ...]:
    """Each body's traction modes on the active nodes of ``frame`` (a
    :class:`ContactFrame`: body 1 receives -lam, body 2 +lam; a
    :class:`~bemcontact.contact.frames.FrameSet`: every pair's): what
    :func:`~bemcontact.contact.condense` condenses each body on for
    :class:`InterfaceSystem`."""
    return _frame_set(frame).traction_modes()


def _frame_set(frame: ContactFrame | FrameSet) -> FrameSet:
    return FrameSet.single(frame) if isinstance(frame, ContactFrame) else frame


#: Entries of a rigid mode's or platen translation's column of dk/dz (and of
#: its equilibrium row) below this fraction of the column's (row's) largest
#: are round-off of an exact zero (docs/theory.md, "Verified solutions").
ROUNDOFF = 1e-11


def _drop_roundoff(M: np.ndarray, axis: int = 0) -> np.ndarray:
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


class InterfaceSystem:
    """The nonsmooth interface system of eq. 17 after condensing the bodies:
    unknowns z = (lam (m active frame nodes x 3, local; every pair's,
    stacked: :class:`~bemcontact.contact.frames.FrameSet`), then per body
    alpha_a, U_a) with alpha the free rigid-mode amplitudes and U the platen
    translations of force-controlled components.  Loads enter through the
    weights ell (S,) over the boundary-condition states.

    ``frame``: the :class:`ContactFrame` of two bodies, or a ``FrameSet``;
    ``cb`` the condensed bodies (in the FrameSet's body order); ``mu`` and
    ``r_scale`` (the augmentation c E*) a number, or one per pair."""

    def __init__(self, frame, cb, mu, r_scale) -> None:
        fs = _frame_set(frame)
        self.frames = fs
        #: the frame of a single pair (None for an assembly)
        self.frame = fs.frames[0] if len(fs.frames) == 1 else None
        self.cb = cb
        npairs = len(fs.frames)
        mu_p = np.broadcast_to(np.asarray(mu, dtype=float), (npairs,))
        rs_p = np.broadcast_to(np.asarray(r_scale, dtype=float), (npairs,))
        #: the friction coefficient of each pair
        self.mu = float(mu_p[0]) if npairs == 1 else mu_p.copy()
        self.act = fs.act[0] if npairs == 1 else None
        m = fs.m
        self.m = m
        a = fs.weights
        self.a = a
        self.area = float(a.sum())
        self.r_scale = rs_p[fs.pair_of]
        self.size = fs.size
        #: the contact law of the frame nodes: friction, augmentation
        #: r_n = r_t = c E*/h_j and the history (:class:`~.law.CoulombLaw`)
        self.law = law.CoulombLaw(mu_p[fs.pair_of], self.r_scale / self.size)
        #: the pair of each node (clusters of the predictor stay in one)
        self.pair_of = fs.pair_of.copy()
        #: an aggregated system's prolongation (3m_fine, 3m) and restriction
        #: (3m, 3m_fine) of tractions (:meth:`aggregated`); None here
        self.prolongation = self.restriction = None
        weighs = [RelativeDisplacement(f, act) for f, act in zip(fs.frames, fs.act)]

        def weigh(G, p, overwrite=False):
            return weighs[p](G, overwrite=overwrite)

        K = np.zeros((3 * m, 3 * m))
        k0X = np.zeros(3 * m)
        k0u = np.zeros((3 * m, cb[0].u0.shape[1]))
        # extra unknowns: per body, alpha then U; L[b] their columns in k
        self.nf = [c.Rc.shape[1] for c in cb]
        self.nc = [c.Yc.shape[1] for c in cb]
        self.L = []
        self.E = []
        self.CT = []  # (nc, 3m): resultants of the controlled components per lam
        self.CY = []  # (nc, nc): ... per platen translation
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
            self.L.append(_drop_roundoff(Li))
            self.L.append(_drop_roundoff(Ly))
            # equilibrium in the free rigid modes, scaled to traction units
            self.E.append(_drop_roundoff(np.asarray((Bt @ Rc).T), axis=1))
            self.CT.append(_drop_roundoff(np.asarray(c.CX), axis=1))
            self.CY.append(c.CY)
        for p in range(npairs):
            dp = fs.dofs(p)
            w = weigh(K[dp], p, overwrite=True)  # in place when projected
            if not np.shares_memory(w, K):
                K[dp] = w
        self.K = K
        self.k0X = k0X
        self.k0u = k0u
        # the history starts from the relative tangential positions
        self.law.reference = k0X.reshape(-1, 3)[:, :2].copy()
        self._dk: tuple | None = None  # (cdofs, cols, K rows): _rows_of_k
        # dk/dz = [K, L...] (3m, nz) and the linear rows besides the law (ne, nz)
        self._Lz = np.hstack([L for L in self.L]) if self.L else np.zeros((3 * m, 0))
        m3, nz = 3 * m, 3 * m + self._Lz.shape[1]
        eq = []
        col = m3
        for i in range(len(cb)):
            nf, nc = self.nf[i], self.nc[i]
            if nf:
                r = np.zeros((nf, nz))
                r[:, :m3] = self.E[i] / self.area
                eq.append(r)
            if nc:
                r = np.zeros((nc, nz))
                r[:, :m3] = self.CT[i] / self.area
                r[:, col + nf : col + nf + nc] = self.CY[i] / self.area
                eq.append(r)
            col += nf + nc
        self._eq = np.vstack(eq) if eq else np.zeros((0, nz))

    # -- vectors
    def zero(self) -> np.ndarray:
        return np.zeros(3 * self.m + sum(self.nf) + sum(self.nc))

    def split(self, z):
        """lam, [alpha_1, U_1, alpha_2, U_2] (the order of self.L)."""
        m3 = 3 * self.m
        parts, o = [], m3
        for nf, nc in zip(self.nf, self.nc):
            parts += [z[o : o + nf], z[o + nf : o + nf + nc]]
            o += nf + nc
        return z[:m3], parts

    def k(self, z: np.ndarray, ell: np.ndarray) -> np.ndarray:
        lam, parts = self.split(z)
        kk = self.k0X + self.k0u @ ell + self.K @ lam
        for L, v in zip(self.L, parts):
            if v.size:
                kk = kk + L @ v
        return kk.reshape(-1, 3)

    def start_increment(self, z: np.ndarray, ell: np.ndarray,
                        reference: np.ndarray | None = None) -> None:
        """Before an increment from the converged ``z`` at load ``ell``, the
        law's history and coefficients in effect (:attr:`law`).  Its stick
        ``reference`` is the relative tangential displacement at ``z``
        (``reference`` instead when given, as the coarse levels of the
        predictor do: their fine system's, restricted).

        A node with a gap at ``z`` closes, if at all, during the increment,
        and its slip is counted from where it touches, which is not known in
        advance.  With the stick reference at the increment's start, the
        tangential part of its approach would be resisted as if it were slip
        (a frame normal tilted against the approach: docs/frame.md).  Such a
        node is frictionless for this increment, and sticks or slips from
        the increment's end on.  A node touching at the start (gap <= 1e-8 of
        its frame element size) keeps its friction, and so do the nodes that
        touch first when every node is open (the smallest gap): they hold
        the bodies from the start (one held laterally only by friction would
        otherwise be free).

        Such a first-touch node (an anchor) holds alone the lateral force
        of the first increment, e.g. the discrete bodies' equilibrium defect
        (1e-4 of the normal force on the Cattaneo-Mindlin sphere): a traction
        growing as 1/h^2, locked in while the node sticks (0.016 / 0.06 p0
        at a/h = 12 / 25).  The anchor holds the bodies; it is no loading
        history: once other nodes of its pair touch, the stick references
        leave out the displacement its tangential traction caused, so the
        increment spreads that force over the contact as an elastic stick
        solution does."""
        law_ = self.law
        kz = self.k(z, ell)
        gap = kz[:, 2]
        tol = 1e-8 * self.size
        npairs = int(self.pair_of.max(initial=-1)) + 1
        # the first touch of each pair (every pair holds its bodies)
        first = np.full(npairs, np.inf)
        np.minimum.at(first, self.pair_of, gap)
        first = np.maximum(first, 0.0)
        law_.mu = np.where(gap > first[self.pair_of] + tol, 0.0, law_.friction)
        touching = gap <= tol
        held = np.zeros(npairs, dtype=bool)  # others than the anchors touch
        np.logical_or.at(held, self.pair_of, touching & ~law_.anchors)
        done = law_.anchors & touching & held[self.pair_of]
        law_.anchors = ((law_.mu > 0.0) & ~touching) | (law_.anchors & ~done)
        if reference is not None:
            law_.reference = reference
            return
        law_.reference = kz[:, :2].copy()
        if not done.any():
            return
        lam = self.split(z)[0].reshape(-1, 3)
        nodes = np.flatnonzero(done)
        cols = (3 * nodes[:, None] + np.arange(2)).ravel()
        dk = (self.K[:, cols] @ lam[nodes, :2].ravel()).reshape(-1, 3)
        law_.reference = law_.reference - dk[:, :2]

    def aggregated(self, groups: np.ndarray) -> InterfaceSystem:
        """The same interface system on clusters of frame nodes: one
        traction per cluster (``groups`` (m,) the cluster of each node,
        0..mc-1), taken by all its nodes (the prolongation P, 0 and 1), and
        one relative displacement per cluster, the area-weighted mean of its
        nodes' (the restriction R = diag(1/a_c) Pᵀ diag(a)); the extra
        unknowns stay.  K_c = R K P, the affine terms and the columns of the
        extra unknowns restricted by R, the equilibrium and resultant rows
        taken on P lam_c (exact for a traction constant over each cluster);
        augmentation r = r_scale / sqrt(cluster area), like a node's.  For
        the coarse-to-fine predictor (:mod:`~bemcontact.contact.predictor`):
        its Newton solve only (no recovery: ``act`` is None)."""
        g = np.asarray(groups, dtype=np.int64)
        if g.shape != (self.m,) or g.min(initial=0) < 0:
            raise ConfigError(
                f"aggregated: one cluster index >= 0 per frame node ({self.m}) expected")
        mc = int(g.max(initial=-1)) + 1
        P1 = scipy.sparse.csr_matrix((np.ones(self.m), (np.arange(self.m), g)), shape=(self.m, mc))
        P = scipy.sparse.kron(P1, scipy.sparse.identity(3), format="csr")
        ac = P1.T @ self.a
        if np.any(ac <= 0.0):
            raise ConfigError("aggregated: every cluster needs at least one frame node")
        R = (scipy.sparse.diags(np.repeat(1.0 / ac, 3)) @ P.T
             @ scipy.sparse.diags(np.repeat(self.a, 3))).tocsr()
        # a cluster lies in one pair (the predictor's clusters do): it takes
        # that pair's friction and augmentation
        pair = np.zeros(mc, dtype=np.int64)
        pair[g] = self.pair_of
        if np.any(pair[g] != self.pair_of):
            raise ConfigError("aggregated: a cluster spans two contact pairs")
        first = np.zeros(mc, dtype=np.int64)
        first[g[::-1]] = np.arange(self.m)[::-1]  # a node of each cluster
        c = object.__new__(InterfaceSystem)
        c.frame, c.frames, c.cb, c.mu, c.act, c.m = self.frame, self.frames, self.cb, self.mu, None, mc
        c.pair_of = pair
        c.a, c.area, c.r_scale = ac, self.area, self.r_scale[first]
        c.size = np.sqrt(P1.T @ self.size**2)
        c.law = law.CoulombLaw(self.law.friction[first], c.r_scale / c.size)
        c.prolongation, c.restriction = P, R
        c.nf, c.nc, c.CY = self.nf, self.nc, self.CY
        RK = R @ self.K  # (3mc, 3m): K is C-ordered, read once
        c.K = np.ascontiguousarray((P.T @ RK.T).T)
        del RK
        c.k0X, c.k0u = R @ self.k0X, R @ self.k0u
        c.law.reference = c.k0X.reshape(-1, 3)[:, :2].copy()
        c.L = [R @ L for L in self.L]
        c.E = [np.asarray((P.T @ E.T).T) for E in self.E]
        c.CT = [np.asarray((P.T @ CT.T).T) for CT in self.CT]
        c._dk = None
        c._Lz = R @ self._Lz
        m3 = 3 * self.m
        c._eq = np.hstack([np.asarray((P.T @ self._eq[:, :m3].T).T), self._eq[:, m3:]])
        return c

    def _rows(self, lam, parts, ell):
        """Linear equations besides the law: free-mode equilibrium and the
        prescribed resultants of controlled components (traction units)."""
        out = []
        for i, c in enumerate(self.cb):
            if self.nf[i]:
                out.append((self.E[i] @ lam + c.known_modal_force @ ell) / self.area)
            if self.nc[i]:
                U = parts[2 * i + 1]
                out.append(
                    (c.control_resultants(ell) + self.CT[i] @ lam + self.CY[i] @ U - c.forces @ ell)
                    / self.area
                )
        return out

    def residual(self, z, ell):
        lam, parts = self.split(z)
        phi = self.law.residual(lam.reshape(-1, 3), self.k(z, ell)).ravel()
        eq = self._rows(lam, parts, ell)
        return np.concatenate([phi, *eq]) if eq else phi

    def _law(self, z, ell):
        lam, _ = self.split(z)
        Jl, Jk, state = self.law.jacobian(lam.reshape(-1, 3), self.k(z, ell))
        closed = np.flatnonzero(state != law.OPEN)
        return Jl, Jk, state, closed, (3 * closed[:, None] + np.arange(3)).ravel()

    def _rows_of_k(self, cdofs, cols) -> np.ndarray:
        """dk/dz of the closed nodes on ``cols``: K's (and the extra
        unknowns') block, kept while the closed set and the columns stay (the
        tangential increments of a fretting or Cattaneo-Mindlin history
        change only stick and slip): its gather from the (3m)^2 K is most of
        the time of :meth:`_block` (Cattaneo-Mindlin a/h = 18: 4.8 s of 7 s
        over 62 Newton systems, measured)."""
        last = self._dk
        if last is not None and np.array_equal(last[0], cdofs) and np.array_equal(last[1], cols):
            return last[2]
        self._dk = None  # the old block goes before the new one is gathered
        m3 = 3 * self.m
        lc, ec = cols[cols < m3], cols[cols >= m3] - m3
        dk = np.empty((cdofs.size, cols.size))
        dk[:, : lc.size] = self.K[np.ix_(cdofs, lc)]
        dk[:, lc.size :] = self._Lz[np.ix_(cdofs, ec)]
        self._dk = (cdofs.copy(), cols.copy(), dk)
        return dk

    def release(self) -> None:
        """Drop the cached rows of K (:meth:`_rows_of_k`) at a solve's end."""
        self._dk = None

    def _block(self, Jl, Jk, closed, cdofs, cols):
        """J[rows, cols] for the rows of the closed nodes (Jl_j on the
        diagonal block + Jk_j dk_j/dz) and the linear rows; ``cols`` sorted,
        containing the closed nodes' own columns."""
        mc = closed.size
        dk = self._rows_of_k(cdofs, cols)
        # C order, as dk: each row a combination of three rows of dk, written
        # contiguously (into a Fortran-ordered J the same combination took
        # 10x longer: 3.3 s against 0.34 s for 8,100 closed dofs); the
        # Newton steps copy it once into LAPACK's Fortran order (NewtonSteps)
        J = np.empty((3 * mc + self._eq.shape[0], cols.size))
        jk = Jk[closed]
        for a in range(3):
            rows = J[a : 3 * mc : 3]
            np.multiply(jk[:, a, 0, None], dk[0::3], out=rows)
            rows += jk[:, a, 1, None] * dk[1::3]
            rows += jk[:, a, 2, None] * dk[2::3]
        if mc:
            own = np.searchsorted(cols, cdofs).reshape(mc, 3)  # columns of each node's own lam
            r = (3 * np.arange(mc)[:, None] + np.arange(3)[None, :])  # (mc, 3) rows
            J[r[:, :, None], own[:, None, :]] += Jl[closed]
        J[3 * mc :] = self._eq[:, cols]
        return J

    def jacobian(self, z, ell):
        """The rows of the generalized Jacobian that are not those of open
        nodes (an open node's row is the identity: lam_j = 0), with every
        column: returns ``(J[rows], rows, state)``."""
        Jl, Jk, state, closed, cdofs = self._law(z, ell)
        m3, nz = 3 * self.m, z.size
        rows = np.concatenate([cdofs, np.arange(m3, nz)])
        return self._block(Jl, Jk, closed, cdofs, np.arange(nz)), rows, state

    def newton_system(self, z, ell, phi):
        """The Newton system J dz = -phi with the open nodes' rows (the
        identity: dz_j = -lam_j) eliminated: returns ``(A, b, keep, state)``
        with A = J[keep, keep] (closed nodes and extra unknowns) and
        b = -phi[keep] - J[keep, open] dz_open; dz[open] = -phi[open]."""
        Jl, Jk, state, closed, cdofs = self._law(z, ell)
        m3, nz = 3 * self.m, z.size
        keep = np.concatenate([cdofs, np.arange(m3, nz)])
        A = self._block(Jl, Jk, closed, cdofs, keep)
        is_open = np.ones(m3, dtype=bool)
        is_open[cdofs] = False
        dlam = np.where(is_open, -phi[:m3], 0.0)  # the open part of dz (extras: 0)
        dk = (self.K @ dlam)[cdofs].reshape(closed.size, 3)
        b = -phi[keep]
        b[: cdofs.size] -= np.einsum("jab,jb->ja", Jk[closed], dk).ravel()
        b[cdofs.size :] -= self._eq[:, :m3] @ dlam
        return A, b, keep, state

    def first_touch(self, z, ell) -> np.ndarray:
        """The starting point of an increment for bodies held only by the
        contact (:func:`~bemcontact.contact.touch.first_touch`)."""
        return first_touch(self, z, ell)


__all__ = ["InterfaceSystem", "RelativeDisplacement", "traction_modes"]
