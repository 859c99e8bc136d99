"""The interface system on the contact grid, solved at the cost of the
contact zone: the augmented-Lagrangian Coulomb law of every cell
(:class:`~bemcontact.contact.law.CoulombLaw`, its history and increment rule
unchanged), the rigid approach and shift of the two bodies, force or
displacement control per component, and a semismooth Newton method whose
directions are computed matrix-free (Newton–Krylov).

Unknowns: the tractions ``p`` (n, 3) on body 2 per cell (global x, y, z =
the law's t1, t2, n; p_z > 0 compressive) and the rigid displacement ``d``
(3,) of body 2 relative to body 1; the relative displacement of the cells is

    k = g0 e_z + d + C p + o        (k_z the gap, > 0 open)

with g0 the initial gap, C the pair's flexibility
(:class:`~.operator.PairOperator`) and o what other pairs' tractions add
through a shared body in an assembly (:attr:`GridInterface.offset`, zero
for a pair alone).  A component of ``d`` is prescribed, or
free with the contact force's component F = A Σ p prescribed (A the cell
area).

A Newton direction.  The law's generalized Jacobian at the current state
makes each open cell's increment explicit (dp = −Φ), and so the tangential
increment of a closed frictionless cell and the slip-direction component of
a slipping one (dp_s = μ dp_n − Φ_s + μ Φ_n).  What remains is one row per
closed cell's normal, per stick cell's tangential component and per slip
cell's component across the slip, each of the form

    (α/β) y + (C dp)·e + dd·e = −Φ·e / β

(β = r for normal and stick rows, α = 1 − c, β = c r across the slip, c = R /
|s_t|).  This system B y = b is solved by GMRES, right-preconditioned with
the circulant approximate inverse of C on the closed cells
(:meth:`~.operator.PairOperator.precondition`), each product one FFT
product with C; the free rigid components are eliminated through their
force rows (one more solve per free component).  The step is taken by the
watchdog line search of the full path
(:class:`~bemcontact.contact.newton.Watchdog`)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse.linalg
import threadpoolctl

from ..contact.law import CoulombLaw
from ..contact.newton import Watchdog
from ..contact.options import SolverOptions
from .operator import PairOperator

#: Largest GMRES iterations per Newton direction solve (restarts included).
MAX_KRYLOV = 400


@dataclass
class GridRecord:
    """One load increment on the grid: Newton iterations, the residual
    history (max |Φ| / traction scale, one per iterate), the Krylov
    iterations of its direction solves, and whether it converged."""

    iterations: int = 0
    residual_history: list = field(default_factory=list)
    krylov_iterations: int = 0
    converged: bool = False
    message: str | None = None


class GridInterface:
    """The contact of two bodies on a grid (see the module docstring).

    ``operator``: the pair's :class:`~.operator.PairOperator`; ``gap`` (n,)
    the initial normal gap at the cell centres; ``friction`` the Coulomb
    coefficient; ``options``: the tolerance, iteration limit, line search
    and augmentation factor (r = penalty E*/h, h the smaller cell side) of
    :class:`~bemcontact.contact.SolverOptions`."""

    def __init__(self, operator: PairOperator, gap: np.ndarray, friction: float,
                 options: SolverOptions | None = None) -> None:
        self.op = operator
        self.grid = operator.grid
        n = self.grid.size
        self.n = n
        self.gap = np.asarray(gap, dtype=float).reshape(n)
        self.options = options or SolverOptions()
        self.h = min(self.grid.dx, self.grid.dy)
        self.area = self.grid.cell_area
        e_star = operator.compliance.contact_modulus
        self.law = CoulombLaw(np.full(n, float(friction)), self.options.penalty * e_star / self.h)
        self.law.reference = np.zeros((n, 2))
        self.p = np.zeros((n, 3))
        self.d = np.zeros(3)
        #: (n, 3) a relative displacement the cells see besides C p: the
        #: other pairs' tractions through a shared body in an assembly
        #: (:mod:`.assembly`); zero for a pair alone
        self.offset = np.zeros((n, 3))
        self._pair_of = np.zeros(n, dtype=np.intp)
        #: the :class:`~.rolling.GridRolling` of the current increment (None:
        #: no rolling)
        self.rolling = None

    # -- fields
    def k(self, p: np.ndarray, d: np.ndarray) -> np.ndarray:
        """(n, 3) relative displacements."""
        k = self.op.matvec(p) + d + self.offset
        k[:, 2] += self.gap
        return k

    def law_k(self, p: np.ndarray, d: np.ndarray) -> np.ndarray:
        """(n, 3) what the law sees: the relative displacements, whose
        tangential part in steady-state rolling is the convected slip per
        shift (I − S)(C p)_t + h w + d_t (:class:`~.rolling.GridRolling`)."""
        k = self.k(p, d)
        if self.rolling is not None and self.rolling.steady:
            k[:, :2] = self.rolling.convected(k[:, :2] - d[:2]) + d[:2]
        return k

    def slip(self) -> np.ndarray:
        """(n, 2) the slip of body 2 relative to body 1 in the current
        increment at the current solution (frame t1, t2 components): the
        law's k_t − reference; per rolled distance when rolling."""
        s = self.law_k(self.p, self.d)[:, :2] - self.law.reference
        if self.rolling is not None:
            s = s / self.rolling.distance
        return s

    def force(self, p: np.ndarray | None = None) -> np.ndarray:
        """(3,) the contact force on body 2 (F_z > 0 compressive)."""
        return self.area * (self.p if p is None else p).sum(axis=0)

    def state(self) -> np.ndarray:
        """(n,) OPEN, STICK or SLIP of each cell at the current solution."""
        return self.law.state(self.p, self.law_k(self.p, self.d))

    # -- one increment
    def snapshot(self) -> tuple:
        """The state an increment starts from (the solution, the offset and
        the law's history), for :meth:`restore`: an increment solved again
        (after a failed predictor, or in an assembly's next sweep) starts
        from the same history, since :meth:`start_increment` moves it on."""
        law = self.law
        return (self.p.copy(), self.d.copy(), self.offset.copy(), law.mu.copy(),
                law.anchors.copy(), law.reference.copy())

    def restore(self, state: tuple) -> None:
        """Back to a :meth:`snapshot`."""
        p, d, offset, mu, anchors, reference = state
        self.p, self.d, self.offset = p.copy(), d.copy(), offset.copy()
        self.law.mu, self.law.anchors, self.law.reference = (mu.copy(), anchors.copy(),
                                                             reference.copy())

    def start_increment(self, rolling=None) -> None:
        """The law's coefficients in effect and stick reference from the
        current solution (:meth:`~bemcontact.contact.law.CoulombLaw.start_increment`),
        or, with ``rolling`` (a :class:`~.rolling.GridRolling`), the
        convected reference (:meth:`~bemcontact.contact.law.CoulombLaw.convect`)."""
        op = self.op
        self.rolling = rolling
        if rolling is not None:
            k_t = self.k(self.p, self.d)[:, :2]
            self.law.convect(np.zeros((self.n, 2)) if rolling.steady
                             else rolling.reference(k_t))
            return

        def influence(nodes, t):
            f = np.zeros((self.n, 3))
            f[nodes, :2] = t
            return op.matvec(f)

        self.law.start_increment(self.k(self.p, self.d), self._pair_of, self.h, self.p,
                                 influence)

    def solve_increment(self, force: np.ndarray, shift: np.ndarray,
                        guess: tuple[np.ndarray, np.ndarray] | None = None,
                        rolling=None, offset: np.ndarray | None = None) -> GridRecord:
        """Solve for the targets: per component, the contact force ``force``
        (3,) where it is finite, else the rigid displacement ``shift`` (3,).
        ``guess``: (tractions (n, 3), rigid displacement (3,)) to start
        Newton from (a coarser grid's solution of the same increment); the
        law's history is taken from the current solution first.

        BLAS runs on one thread: its only work here is on vectors and the
        Krylov basis, where a second thread halves no wall time and doubles
        the CPU time (measured at a/h = 25: 0.95 s wall either way, 1.87 s
        CPU with two threads, 0.94 s with one).

        ``rolling`` (a :class:`~.rolling.GridRolling`): the increment rolls.
        In steady state a tangential component's rigid displacement is the
        extra creepage times the cell size that carries its force where
        ``force`` is finite, else zero (``shift`` is not used there).

        ``offset`` (n, 3): the :attr:`offset` of this increment (an
        assembly's other pairs at their new load), in effect after the law's
        history is taken (with the previous one, the converged state's)."""
        with threadpoolctl.threadpool_limits(limits=1, user_api="blas"):
            return self._solve_increment(force, shift, guess, rolling, offset)

    def _solve_increment(self, force, shift, guess, rolling, offset) -> GridRecord:
        force = np.asarray(force, dtype=float)
        shift = np.asarray(shift, dtype=float)
        free = np.flatnonzero(np.isfinite(force))
        fixed = np.flatnonzero(~np.isfinite(force))
        # the law's history from the state the increment starts from (the
        # converged one, at the previous load), then the new prescribed shift
        self.start_increment(rolling)
        if offset is not None:
            self.offset = np.asarray(offset, dtype=float).reshape(self.n, 3)
        if rolling is not None and rolling.steady:
            shift = shift.copy()
            shift[:2] = 0.0
        elif rolling is not None and guess is None:
            # transient: Newton starts from the tangential tractions carried
            # with the material (measured: 4 iterations for the first
            # increment of a Cattaneo contact rolling, 16 from the tractions
            # left in place)
            self.p[:, :2] = rolling.shift(self.p[:, :2], rolling.distance)
        self.d[fixed] = shift[fixed]
        if guess is not None:
            self.p = np.array(guess[0], dtype=float).reshape(self.n, 3)
            self.d[free] = np.asarray(guess[1], dtype=float)[free]
        elif 2 in free:
            self._first_touch(force[2])
        opt = self.options
        rec = GridRecord()
        total_area = self.area * self.n

        def residual(z):
            p, d = self._unpack(z, free)
            phi = self.law.residual(p, self.law_k(p, d)).ravel()
            rho = (self.area * p[:, free].sum(axis=0) - force[free]) / total_area
            return np.concatenate([phi, rho])

        z = self._pack(free)
        phi = residual(z)
        scale = max(np.abs(phi).max(initial=0.0), np.abs(self.p).max(initial=0.0),
                    abs(force[2]) / total_area if 2 in free else 0.0, 1e-300)
        search = Watchdog(opt.line_search_sigma, opt.watchdog, opt.min_step)
        it = 0
        while True:
            p, d = self._unpack(z, free)
            lam_scale = max(scale, np.abs(p).max(initial=0.0))
            err = float(np.abs(phi).max(initial=0.0) / lam_scale)
            rec.residual_history.append(err)
            if err <= opt.tolerance:
                rec.converged = True
                break
            if it >= opt.max_iterations:
                rec.message = f"no convergence in {opt.max_iterations} iterations"
                break
            forcing = min(1e-2, max(0.1 * opt.tolerance, 0.1 * err))
            step = self._direction(p, d, free, force, phi, forcing, rec)
            if isinstance(step, str):
                rec.message = step
                break
            taken = search.step(residual, z, step, 0.5 * float(phi @ phi))
            if taken is None:
                rec.message = ("line search failed (no decrease of the residual along the "
                               "Newton direction)")
                break
            z, phi, _ = taken
            it += 1
        rec.iterations = it
        self.p, self.d = self._unpack(z, free)
        return rec

    def _pack(self, free):
        return np.concatenate([self.p.ravel(), self.d[free]])

    def _unpack(self, z, free):
        p = z[: 3 * self.n].reshape(self.n, 3)
        d = self.d.copy()
        d[free] = z[3 * self.n:]
        return p, d

    def _first_touch(self, target: float) -> None:
        """A normal force to carry with every cell open: the approach that a
        flat punch of the overlapping cells' area would need for it (twice
        the punch's, the ratio of a Hertz contact's approach to that of a
        punch of its geometric overlap), so that Newton starts from a patch
        of about the right size."""
        if target <= 0.0:
            return
        k = self.k(self.p, self.d)
        r = self.law.r
        if np.any(self.p[:, 2] - r * k[:, 2] > 0.0):
            return
        g = np.sort(k[:, 2])
        e_star = self.op.compliance.contact_modulus
        counts = np.arange(1, g.size + 1)
        # eta(j) = g[j] - g[0] against the punch approach with j + 1 cells
        need = target * math.sqrt(math.pi) / (e_star * np.sqrt(counts * self.area))
        j = int(np.searchsorted(g - g[0] - need, 0.0))
        j = min(max(j, 1), g.size - 1)
        self.d[2] -= g[j]

    def _direction(self, p, d, free, force, phi, forcing, rec):
        """The Newton step dz = (dp, dd_free) (see the module docstring), or
        a message when it cannot be computed."""
        n = self.n
        law = self.law
        r = law.r
        mu = np.broadcast_to(law.mu, (n,))
        k = self.law_k(p, d)
        Phi = phi[: 3 * n].reshape(n, 3)
        sn = p[:, 2] - r * k[:, 2]
        closed = sn > 0.0
        st = p[:, :2] - r[:, None] * (k[:, :2] - law.reference)
        ns = np.linalg.norm(st, axis=1)
        R = mu * np.maximum(sn, 0.0)
        fric = closed & (mu > 0.0)
        stick = fric & (ns <= R)
        slip = fric & ~stick
        loose = closed & ~fric
        s = np.zeros((n, 2))
        s[:, 0] = 1.0
        s[slip] = st[slip] / ns[slip, None]
        perp = np.stack([-s[:, 1], s[:, 0]], axis=1)
        c = np.zeros(n)
        c[slip] = R[slip] / ns[slip]

        known = np.zeros((n, 3))
        known[~closed] = -Phi[~closed]
        known[loose, :2] = -Phi[loose, :2]
        phis = np.einsum("ij,ij->i", Phi[slip, :2], s[slip])
        known[slip, :2] = ((-phis + mu[slip] * Phi[slip, 2])[:, None]) * s[slip]

        # the rows: normal of every closed cell, both tangential of a stick
        # cell, across the slip of a slipping one
        cn = np.flatnonzero(closed)
        cs = np.flatnonzero(stick)
        cp = np.flatnonzero(slip)
        cells = np.concatenate([cn, cs, cs, cp])
        direction = np.zeros((cells.size, 3))
        direction[: cn.size, 2] = 1.0
        o = cn.size
        direction[o: o + cs.size, 0] = 1.0
        direction[o + cs.size: o + 2 * cs.size, 1] = 1.0
        direction[o + 2 * cs.size:, :2] = perp[cp]
        vec = direction.copy()
        vec[: cn.size, :2] = (mu[cn] * slip[cn])[:, None] * s[cn]
        beta = np.concatenate([r[cn], r[cs], r[cs], c[cp] * r[cp]])
        diag = np.zeros(cells.size)
        diag[o + 2 * cs.size:] = (1.0 - c[cp]) / beta[o + 2 * cs.size:]
        rhs = -np.einsum("ij,ij->i", Phi[cells], direction) / beta

        if cells.size == 0:
            # nothing in contact at this iterate: a free component keeps its
            # rigid displacement, which only a zero force allows
            if np.any(force[free] != 0.0):
                return "no cell is in contact: the prescribed force cannot be carried"
            return np.concatenate([(-Phi).ravel(), np.zeros(free.size)])

        def scatter(y, v):
            out = np.empty((n, 3))
            for comp in range(3):
                out[:, comp] = np.bincount(cells, weights=y * v[:, comp], minlength=n)
            return out

        def gather(u):
            return np.einsum("ij,ij->i", u[cells], direction)

        op = self.op
        roll = self.rolling if self.rolling is not None and self.rolling.steady else None

        def product(f):
            """C f, its tangential part convected in steady rolling."""
            u = op.matvec(f)
            if roll is not None:
                u[:, :2] = roll.difference(u[:, :2])
            return u

        def B(y):
            return diag * y + gather(product(scatter(y, vec)))

        # rows whose own traction term outweighs their cell's self-flexibility
        # (across a fast slip, c small) are preconditioned by their diagonal;
        # the others by the circulant inverse of C on the cells they share
        # (in steady rolling, of (I − S) C: C's inverse after (I − S)'s)
        block = op.self_block.copy()
        if roll is not None:
            nx, ny = self.grid.shape
            di, dj = roll.neighbour_offset()
            block[:2] -= op.halfspace.blocks[nx - 1 + di, ny - 1 + dj][:2]
        own = np.einsum("ij,jk,ik->i", direction, block, direction)
        heavy = diag > own
        light = ~heavy
        inv_heavy = 1.0 / (diag[heavy] + own[heavy])
        cells_l, dir_l = cells[light], direction[light]

        def M(x):
            out = np.empty_like(x)
            out[heavy] = x[heavy] * inv_heavy
            f = np.empty((n, 3))
            for comp in range(3):
                f[:, comp] = np.bincount(cells_l, weights=x[light] * dir_l[:, comp], minlength=n)
            if roll is not None:
                f[:, :2] = roll.undifference(f[:, :2])
            out[light] = np.einsum("ij,ij->i", op.precondition(f)[cells_l], dir_l)
            return out

        m = cells.size
        nf = free.size
        # the free rigid components' columns D and force rows G (scaled to
        # the displacement rows), eliminated in the preconditioner with the
        # approximate Schur complement G M D (block-triangular, right)
        D = direction[:, free]
        cscale = self.area * m * op.compliance.contact_modulus / self.h
        G = (self.area / cscale) * vec[:, free].T
        W = np.array([M(D[:, j]) for j in range(nf)]).T.reshape(m, nf)
        Sc = G @ W
        held = free
        if nf and (not np.all(np.isfinite(Sc)) or abs(np.linalg.det(Sc)) == 0.0):
            if not np.any(D) and np.any(fric):
                # no row of this iterate sees the free components although
                # friction could hold them (every closed cell slips across
                # them, a state Newton may pass through in transient
                # rolling): the direction holds them and leaves their force
                # rows to the next iterates; without friction nothing can
                # hold them, and the matrix is singular
                nf, held = 0, free[:0]
                D, G, W, Sc = D[:, :0], G[:0], W[:, :0], Sc[:0, :0]
            else:
                return ("the Newton matrix is singular: a free rigid component is not held by "
                        "the contact")

        def P(v):
            u = M(v[:m])
            if not nf:
                return u, np.zeros(0)
            delta = np.linalg.solve(Sc, G @ u - v[m:])
            return u - W @ delta, delta

        def A(v):
            y, delta = P(v)
            return np.concatenate([B(y) + D @ delta, G @ y])

        rho = self.area * p[:, held].sum(axis=0) - force[held]
        b0 = rhs - gather(product(known))
        g = (-rho - self.area * known[:, held].sum(axis=0)) / cscale
        rhs_aug = np.concatenate([b0, g])
        count = [0]

        def cb(_):
            count[0] += 1

        x = np.zeros(m + nf)
        if np.linalg.norm(rhs_aug) > 0.0:
            AP = scipy.sparse.linalg.LinearOperator((m + nf, m + nf), matvec=A, dtype=float)
            x, info = scipy.sparse.linalg.gmres(AP, rhs_aug, rtol=forcing, atol=0.0, restart=80,
                                                maxiter=MAX_KRYLOV // 80 + 1, callback=cb,
                                                callback_type="pr_norm")
            rec.krylov_iterations += count[0]
            if info != 0 or not np.all(np.isfinite(x)):
                return "the Newton system's Krylov solve did not converge"
        y0, dd = P(x)
        dp = known + scatter(y0, vec)
        return np.concatenate([dp.ravel(), dd if held.size == free.size else
                               np.zeros(free.size)])


__all__ = ["GridInterface", "GridRecord", "MAX_KRYLOV"]
