"""The interface system of eq. 17 after condensing the bodies: unknowns,
the affine map to the frame's relative displacements k, the residual of the
contact law and the other linear rows, the generalized Jacobian and the
first-touch predictor.  Solved by :mod:`bemcontact.contact.newton`; results
recovered by :mod:`bemcontact.contact.recovery`."""

from __future__ import annotations


import numpy as np

from . import law
from .frame import ContactFrame
from .frames import FrameSet
from .kinematics import Kinematics
from .modes import TractionModes
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
        npairs = len(fs.frames)
        mu_p = np.broadcast_to(np.asarray(mu, dtype=float), (npairs,))
        rs_p = np.broadcast_to(np.asarray(r_scale, dtype=float), (npairs,))
        kin = Kinematics.assemble(fs, cb)
        self._set(fs, cb, float(mu_p[0]) if npairs == 1 else mu_p.copy(),
                  fs.act[0] if npairs == 1 else None, fs.weights, fs.size, fs.pair_of.copy(),
                  mu_p[fs.pair_of], rs_p[fs.pair_of], kin, kin.extra_columns(),
                  kin.linear_rows(float(fs.weights.sum())))

    @classmethod
    def from_parts(cls, frames, cb, mu, act, a, size, pair_of, friction, r_scale,
                   kinematics, Lz, eq, prolongation=None, restriction=None,
                   area=None) -> InterfaceSystem:
        """An interface system from its parts (the predictor's aggregated
        systems: :func:`~bemcontact.contact.predictor.aggregated`)."""
        self = cls.__new__(cls)
        self._set(frames, cb, mu, act, a, size, pair_of, friction, r_scale, kinematics, Lz,
                  eq, prolongation, restriction, area)
        return self

    def _set(self, frames, cb, mu, act, a, size, pair_of, friction, r_scale, kin, Lz, eq,
             prolongation=None, restriction=None, area=None) -> None:
        """Every attribute, in one place: the frames and flexibilities; the
        friction coefficient of each pair ``mu``; the active nodes of a
        single pair ``act`` (None for an assembly or a coarse level); per
        node its weight ``a``, size, pair, friction and augmentation scale;
        the :class:`~.kinematics.Kinematics`, its extra unknowns' columns
        ``Lz`` and the linear rows ``eq``; a coarse level's prolongation and
        restriction of tractions."""
        self.frames = frames
        #: the frame of a single pair (None for an assembly)
        self.frame = frames.frames[0] if len(frames.frames) == 1 else None
        self.cb = cb
        #: the friction coefficient of each pair
        self.mu = mu
        self.act = act
        self.a = a
        self.m = a.size
        self.area = float(a.sum()) if area is None else area
        self.size = size
        #: the pair of each node (clusters of the predictor stay in one)
        self.pair_of = pair_of
        self.r_scale = r_scale
        #: the contact law of the frame nodes: friction, augmentation
        #: r_n = r_t = c E*/h_j and the history (:class:`~.law.CoulombLaw`)
        self.law = law.CoulombLaw(friction, r_scale / size)
        #: an aggregated system's prolongation (3m_fine, 3m) and restriction
        #: (3m, 3m_fine) of tractions; None here
        self.prolongation, self.restriction = prolongation, restriction
        self.kinematics = kin
        self.K, self.k0X, self.k0u = kin.K, kin.k0X, kin.k0u
        self.L, self.E, self.CT, self.CY = kin.L, kin.E, kin.CT, kin.CY
        self.nf, self.nc = kin.nf, kin.nc
        # the history starts from the relative tangential positions
        self.law.reference = self.k0X.reshape(-1, 3)[:, :2].copy()
        self._dk: tuple | None = None  # (cdofs, cols, K rows): _rows_of_k
        #: what the law sees in a steady rolling step: the affine map
        #: (K, k0X, k0u) with its tangential rows differenced (:meth:`roll`);
        #: None: the physical map k(z)
        self._law_map = None
        #: the :class:`~bemcontact.contact.rolling.FrameRolling` of the
        #: current increment (None: no rolling)
        self.rolling = None
        # dk/dz = [K, L...] (3m, nz) and the linear rows besides the law (ne, nz)
        self._Lz, self._eq = Lz, eq

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
        return self._affine(z, ell, self.K, self.k0X, self.k0u)

    def _affine(self, z, ell, K, k0X, k0u) -> np.ndarray:
        """(m, 3) k0X + k0u ell + K lam + L v: the physical map or the law's."""
        lam, parts = self.split(z)
        kk = k0X + k0u @ ell + K @ lam
        for L, v in zip(self.L, parts):
            if v.size:
                kk = kk + L @ v
        return kk.reshape(-1, 3)

    def law_k(self, z: np.ndarray, ell: np.ndarray) -> np.ndarray:
        """(m, 3) what the law sees: :meth:`k`, whose tangential part in a
        steady rolling step is the convected slip per shift (:meth:`roll`)."""
        if self._law_map is None:
            return self.k(z, ell)
        return self._affine(z, ell, *self._law_map[:3])

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
        kz = self.k(z, ell)
        lam = self.split(z)[0].reshape(-1, 3)

        def influence(nodes, t):
            cols = (3 * nodes[:, None] + np.arange(2)).ravel()
            return (self.K[:, cols] @ t.ravel()).reshape(-1, 3)

        self.law.start_increment(kz, self.pair_of, self.size, lam, influence, reference)

    def roll(self, z: np.ndarray, ell: np.ndarray, rolling=None) -> None:
        """Before an increment of a rolling step (a
        :class:`~bemcontact.contact.rolling.FrameRolling`; instead of
        :meth:`start_increment`), from the converged ``z`` at load ``ell``:
        the law's convected stick reference (:meth:`~.law.CoulombLaw.convect`).
        Transient: S k_t − Δq w.  Steady: the law sees the convected slip per
        shift, k_t → (I − S)(K λ + k0u ℓ)_t + Δq w + (L v)_t, so the affine
        map's tangential rows are differenced here (the rigid unknowns' L v
        is not: a force-controlled component's platen shift becomes Δq times
        its extra creepage, as on the grid) and the reference is zero
        (:meth:`law_k`; :meth:`k` stays the physical map).  ``rolling``
        None: :meth:`start_increment`."""
        if rolling is None:
            if self._law_map is not None:
                self._law_map, self._dk = None, None
            self.rolling = None
            self.start_increment(z, ell)
            return
        self.rolling = rolling
        if not rolling.steady:
            self._law_map, self._dk = None, None
            # the material's displacement is convected, not the initial
            # relative positions k0X (geometry, nonzero on non-matching meshes)
            k0 = self.k0X.reshape(-1, 3)[:, :2]
            self.law.convect(rolling.reference(self.k(z, ell)[:, :2] - k0) + k0)
            return
        if self._law_map is None or self._law_map[3] is not rolling:
            t = np.sort(np.concatenate([np.arange(0, 3 * self.m, 3),
                                        np.arange(1, 3 * self.m, 3)]))
            S = rolling.S
            K = self.K.copy()
            K[t] -= S @ self.K[t]
            k0u = self.k0u.copy()
            k0u[t] -= S @ self.k0u[t]
            k0X = self.k0X.copy()
            k0X[t] = (rolling.distance[:, None] * rolling.w).ravel()
            self._law_map, self._dk = (K, k0X, k0u, rolling), None
        self.law.convect(np.zeros((self.m, 2)))

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
        phi = self.law.residual(lam.reshape(-1, 3), self.law_k(z, ell)).ravel()
        eq = self._rows(lam, parts, ell)
        return np.concatenate([phi, *eq]) if eq else phi

    def _law(self, z, ell):
        lam, _ = self.split(z)
        Jl, Jk, state = self.law.jacobian(lam.reshape(-1, 3), self.law_k(z, ell))
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
        K = self.K if self._law_map is None else self._law_map[0]
        dk[:, : lc.size] = K[np.ix_(cdofs, lc)]
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
        K = self.K if self._law_map is None else self._law_map[0]
        dk = (K @ dlam)[cdofs].reshape(closed.size, 3)
        b = -phi[keep]
        b[: cdofs.size] -= np.einsum("jab,jb->ja", Jk[closed], dk).ravel()
        b[cdofs.size :] -= self._eq[:, :m3] @ dlam
        return A, b, keep, state

    def first_touch(self, z, ell) -> np.ndarray:
        """The starting point of an increment for bodies held only by the
        contact (:func:`~bemcontact.contact.touch.first_touch`)."""
        return first_touch(self, z, ell)


__all__ = ["InterfaceSystem", "traction_modes"]
