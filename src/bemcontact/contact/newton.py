"""The generalized Newton method with a watchdog line search (Pang 1990;
founding paper, GNMLS) on the condensed interface system.

Each iteration solves the generalized Jacobian system with the contact state
frozen (:func:`newton_direction`); the step is taken by the watchdog
non-monotone line search (:class:`Watchdog`): a few full steps are tried
without a decrease of the merit Psi = 1/2 |Phi|^2, then the search returns to
the best point and halves the step along its direction until Psi decreases by
the factor (1 - 2 sigma alpha).
"""

from __future__ import annotations

import warnings
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import scipy.linalg
import scipy.sparse.linalg

from ..progress import ProgressEvent, Reporter
from .options import SolverOptions
from .results import StepRecord

#: Smallest reduced Newton system (unknowns) solved by GMRES with a reused
#: or single-precision factorization when ``newton_steps = "mixed"``; below
#: it a double LU in every iteration is as cheap and gives the LU path's
#: iterates bitwise.  Measured on Cattaneo–Mindlin with the predictor
#: (30 Newton iterations, the same iterates to 1e-13): at a/h = 12, blocks
#: of 1,600-2,500 unknowns, 5.9-6.8 s with double LUs, 6.3-7.0 s mixed; at
#: a/h = 18, blocks of up to 3,600, 39.7 s with double LUs, 29.9 s mixed.
SINGLE_MIN = 3000

#: Message of a Newton matrix too close to singular.
SINGULAR = (
    "the Newton matrix is singular: a body is free to move (rigid motion not restrained by "
    "supports or by contact, e.g. a force that pulls a body held only by the contact away "
    "from it) or the contact surfaces do not face each other"
)


class NewtonSteps:
    """The Newton directions of a solve: J dz = -phi with the open nodes'
    rows eliminated (:meth:`~bemcontact.contact.interface.
    InterfaceSystem.newton_system`), the reduced matrix A of the closed
    nodes and extra unknowns solved by dense LU (``reuse`` False: a double
    LU in every iteration).

    With ``reuse`` (``[solver] newton_steps = "mixed"``), for systems of at
    least :data:`SINGLE_MIN` unknowns, a new factorization is a
    single-precision LU, the preconditioner of GMRES to ``forcing`` x |b|
    (1-2 iterations; a double LU whenever GMRES does not converge).
    Measured at Cattaneo–Mindlin a/h = 25 (blocks of up to 8,000 unknowns):
    5.7 s per iteration with double LUs, 4.85 s with single ones and GMRES
    (76 GMRES iterations for 67 steps), the same iterates.

    Reusing a factorization across iterations (``max_change`` >= 0, off by
    default): A changes from one
    iteration to the next only in the law blocks of the nodes whose contact
    state changed (and, a little, in those of slipping nodes), so while the
    closed set differs from that of the last factorization by at most
    ``max_change`` of its size, A is solved by GMRES preconditioned with that
    LU (on the shared dofs; the diagonal on nodes closed since), within a
    budget of iterations cheaper than a new factorization, and a new
    factorization is a single-precision LU used the same way (half the time
    of the double one) — for systems of at least :data:`SINGLE_MIN`
    unknowns; smaller ones are factored in double every iteration.  GMRES runs to
    ``forcing`` x |b| (default 1e-10: the steps of the exact method, so the
    same iterates; a looser min(1e-2, 0.1 err) changes the path: 10 and 13
    iterations where the exact steps take 9 and 7).  Whenever GMRES does not
    converge, or the single-precision LU has a pivot below 1e-7 of the
    largest, the double LU is computed, with its singularity diagnosis.
    Measured on Cattaneo–Mindlin at a/h = 25 (closed blocks of up to 8,000
    unknowns): Newton 291 s (19 factorizations, 2,578 GMRES iterations)
    against 390 s with a double LU in every iteration (68), the same
    iterates to 1e-15.  The factorization
    is kept across increments (in a tangential increment the closed set
    stays, only stick and slip change).  ``stats`` counts factorizations and
    Krylov iterations."""

    def __init__(self, reuse: bool = True, max_krylov: int = 60, max_change: float = -1.0) -> None:
        self.reuse = reuse
        self.max_change = max_change
        self.max_krylov = max_krylov
        self._last: tuple | None = None  # (keep, lu)
        self.stats = {"factorizations": 0, "krylov_steps": 0, "krylov_iterations": 0,
                      "krylov_failures": 0}

    def __call__(self, A: np.ndarray, b: np.ndarray, keep: np.ndarray, phi: np.ndarray,
                 forcing: float = 1e-10) -> np.ndarray | str:
        """dz with A dz[keep] = b and dz = -phi on every other row (an open
        node's lam = 0); a message instead when the matrix is not usable or
        singular."""
        dz = -phi.copy()
        if not keep.size:
            return dz
        large = self.reuse and keep.size >= SINGLE_MIN
        if large and self._last is not None:
            old, lu = self._last
            common = np.intersect1d(old, keep, assume_unique=True).size
            if keep.size + old.size - 2 * common <= self.max_change * keep.size:
                x = self._krylov(A, b, keep, old, lu, forcing)
                if x is not None:
                    dz[keep] = x
                    return dz
        if large and np.all(np.isfinite(A)):
            # a single-precision LU (half the time and memory of LAPACK's
            # dgetrf) as preconditioner: GMRES reaches the forcing in a few
            # iterations unless A is (nearly) singular, which the double
            # LU below then diagnoses
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", scipy.linalg.LinAlgWarning)
                lu = _factor(A, single=True)
            self.stats["factorizations"] += 1
            d = np.abs(np.diag(lu[0]))
            if np.isfinite(d).all() and d.min() > 1e-7 * d.max():
                x = self._krylov(A, b, keep, keep, lu, forcing)
                if x is not None:
                    self._last = (keep, lu)
                    dz[keep] = x
                    return dz
        try:
            with warnings.catch_warnings():
                # exact singularity is diagnosed below, with a better message
                warnings.simplefilter("ignore", scipy.linalg.LinAlgWarning)
                lu = _factor(A, check_finite=True)
        except (ValueError, np.linalg.LinAlgError) as exc:
            return f"the Newton matrix is not usable ({exc})"
        self.stats["factorizations"] += 1
        d = np.abs(np.diag(lu[0]))
        if d.min() <= 1e-13 * d.max():
            return SINGULAR
        self._last = (keep, lu)
        dz[keep] = scipy.linalg.lu_solve(lu, b, check_finite=False)
        return dz

    def _krylov(self, A, b, keep, old, lu, forcing):
        """GMRES on A x = b preconditioned by the LU of the last factored
        matrix (on the dofs both share; the diagonal on the new ones)."""
        n = b.size
        dtype = lu[0].dtype

        def solve(v):
            return scipy.linalg.lu_solve(lu, v.astype(dtype, copy=False),
                                        check_finite=False).astype(float, copy=False)

        if np.array_equal(old, keep):
            apply = solve
        else:
            in_old = np.searchsorted(old, keep)
            in_old = np.minimum(in_old, old.size - 1)
            shared = old[in_old] == keep
            at_old = in_old[shared]
            new = ~shared  # law dofs of nodes closed since (nonzero diagonal)
            dinv = 1.0 / np.diag(A)[new]

            def apply(v):
                w = np.zeros(old.size)
                w[at_old] = v[shared]
                y = solve(w)
                out = np.empty_like(v)
                out[shared] = y[at_old]
                out[new] = v[new] * dinv
                return out
        pre = scipy.sparse.linalg.LinearOperator((n, n), apply)
        count = [0]

        def cb(_):
            count[0] += 1

        # a budget of iterations cheaper than a factorization: an iteration
        # costs a product with A and an LU solve (memory bound: ~80 ms at
        # n = 7,000), the LU 2/3 n^3 flops at BLAS-3 speed (~5 s there)
        budget = int(min(self.max_krylov, max(30, n / 120)))
        x, info = scipy.sparse.linalg.gmres(A, b, x0=apply(b), rtol=forcing, atol=0.0, M=pre,
                                            restart=-(-budget // 2), maxiter=2,
                                            callback=cb, callback_type="pr_norm")
        self.stats["krylov_steps"] += 1
        self.stats["krylov_iterations"] += count[0]
        if info == 0 and np.all(np.isfinite(x)):
            return x
        self.stats["krylov_failures"] += 1
        return None


def _factor(A: np.ndarray, single: bool = False, check_finite: bool = False) -> tuple:
    """LU factors (lu, piv) of the C-ordered Newton matrix A
    (:meth:`~bemcontact.contact.interface.InterfaceSystem.newton_system`
    builds it row by row), in single precision with ``single``: one
    transposing copy into the Fortran order LAPACK factors in place (0.4 s
    for 8,100 unknowns, against 3 s more to build A in Fortran order)."""
    M = A.astype(np.float32 if single else float, order="F", copy=not A.flags.f_contiguous)
    return scipy.linalg.lu_factor(M, check_finite=check_finite, overwrite_a=True)


def newton_direction(A: np.ndarray, b: np.ndarray, keep: np.ndarray,
                     phi: np.ndarray) -> np.ndarray | str:
    """One Newton direction by a fresh LU (:class:`NewtonSteps` without reuse)."""
    return NewtonSteps(reuse=False)(A, b, keep, phi)


@dataclass
class Watchdog:
    """The watchdog non-monotone line search (see the module docstring).

    ``watchdog`` full steps are allowed without a sufficient decrease since
    the reference point ``best`` = (z, Psi, direction); then the search goes
    back to it and backtracks (monotone Armijo search on every step when
    ``watchdog`` is 0)."""

    sigma: float
    watchdog: int
    min_step: float
    best: tuple | None = None
    trial: int = 0

    def step(self, residual: Callable[[np.ndarray], np.ndarray], z: np.ndarray,
             dz: np.ndarray, psi: float) -> tuple[np.ndarray, np.ndarray, float] | None:
        """(z_new, Phi(z_new), alpha) from the point ``z`` with merit ``psi``
        along the Newton direction ``dz``; None when the backtracking falls
        below ``min_step``."""
        if self.best is None or psi <= (1 - 2 * self.sigma) * self.best[1]:
            # sufficient decrease since the reference point: it becomes the new one
            self.best, self.trial = (z, psi, dz), 0
        if self.trial < self.watchdog:
            # a full step, judged by the next iterations
            zt = z + dz
            self.trial += 1
            return zt, residual(zt), 1.0
        # no decrease within the watchdog's steps: back to the reference point,
        # monotone line search along its Newton direction
        z0, psi0, d0 = self.best
        alpha = 1.0 if self.watchdog == 0 else 0.5
        while True:
            zt = z0 + alpha * d0
            pt = residual(zt)
            if 0.5 * float(pt @ pt) <= (1 - 2 * self.sigma * alpha) * psi0:
                break
            alpha *= 0.5
            if alpha < self.min_step:
                break
        if alpha < self.min_step:
            return None
        self.best, self.trial = None, 0
        return zt, pt, alpha


def newton(system, z: np.ndarray, ell: np.ndarray, opt: SolverOptions,
           report: Reporter | None = None, index: int = 0, total: int = 0,
           solver: NewtonSteps | None = None):
    """Solve one load increment of the interface system ``system``
    (:class:`~bemcontact.contact.interface.InterfaceSystem`) from ``z``:
    returns (z, :class:`StepRecord`, message), the message None on
    convergence (max |Phi| <= tolerance x traction scale).  ``solver``: the
    step solver, kept across increments to reuse its factorization (default
    a new one as ``opt.newton_steps`` says)."""
    hist: list[float] = []
    steps: list[float] = []
    z = system.first_touch(z, ell)
    phi = system.residual(z, ell)
    m3 = 3 * system.m
    scale = max(np.abs(phi).max(initial=0.0), np.abs(z[:m3]).max(initial=0.0), 1e-300)
    search = Watchdog(opt.line_search_sigma, opt.watchdog, opt.min_step)
    if solver is None:
        solver = NewtonSteps(reuse=opt.newton_steps == "mixed")
    before = dict(solver.stats)
    it = 0
    msg = None
    while True:
        lam_scale = max(scale, np.abs(z[:m3]).max(initial=0.0))
        err = np.abs(phi).max(initial=0.0) / lam_scale
        hist.append(float(err))
        if report is not None:
            report(ProgressEvent("iteration", "newton", "", index=index, total=total,
                                 iteration=it, residual=float(err)))
        if err <= opt.tolerance:
            break
        if it >= opt.max_iterations:
            msg = f"no convergence in {opt.max_iterations} iterations"
            break
        A, b, keep, _ = system.newton_system(z, ell, phi)
        dz = solver(A, b, keep, phi)
        del A
        if isinstance(dz, str):
            msg = dz
            break
        taken = search.step(lambda v: system.residual(v, ell), z, dz,
                            0.5 * float(phi @ phi))
        if taken is None:
            msg = "line search failed (no decrease of the residual along the Newton direction)"
            break
        z, phi, alpha = taken
        steps.append(alpha)
        it += 1
    rec = StepRecord(1.0, it, hist, msg is None, steps)
    rec.factorizations = solver.stats["factorizations"] - before["factorizations"]
    rec.krylov_iterations = solver.stats["krylov_iterations"] - before["krylov_iterations"]
    return z, rec, msg


__all__ = ["newton", "newton_direction", "NewtonSteps", "Watchdog"]
