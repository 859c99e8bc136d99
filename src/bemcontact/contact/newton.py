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

from ..progress import ProgressEvent, Reporter
from .options import SolverOptions
from .results import StepRecord

#: Message of a Newton matrix too close to singular.
SINGULAR = (
    "the Newton matrix is singular: a body is free to move (rigid motion not restrained by "
    "supports or by contact, e.g. a force that pulls a body held only by the contact away "
    "from it) or the contact surfaces do not face each other"
)


def newton_direction(J: np.ndarray, keep: np.ndarray, phi: np.ndarray) -> np.ndarray | str:
    """The Newton direction dz with J dz = -phi, for ``J`` the rows ``keep``
    of the generalized Jacobian (every other row is the identity: an open
    node's lam = 0): those rows are eliminated and only the closed nodes and
    the extra unknowns are factored (dense LU).  Returns a message instead
    when the matrix is not usable or singular."""
    is_open = np.ones(phi.size, dtype=bool)
    is_open[keep] = False
    dz = np.zeros_like(phi)
    dz[is_open] = -phi[is_open]
    if not keep.size:
        return dz
    Jkk = J[:, keep]
    rhs = -phi[keep] - J @ dz  # dz holds only the open rows yet
    try:
        with warnings.catch_warnings():
            # exact singularity is diagnosed below, with a better message
            warnings.simplefilter("ignore", scipy.linalg.LinAlgWarning)
            lu = scipy.linalg.lu_factor(Jkk, check_finite=True)
    except (ValueError, np.linalg.LinAlgError) as exc:
        return f"the Newton matrix is not usable ({exc})"
    d = np.abs(np.diag(lu[0]))
    if d.min() <= 1e-13 * d.max():
        return SINGULAR
    dz[keep] = scipy.linalg.lu_solve(lu, rhs)
    return dz


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


def newton(system, z: np.ndarray, ell: np.ndarray, k_prev: np.ndarray, opt: SolverOptions,
           report: Reporter | None = None, index: int = 0, total: int = 0):
    """Solve one load increment of the interface system ``system``
    (:class:`~bemcontact.contact.interface.InterfaceSystem`) from ``z``:
    returns (z, :class:`StepRecord`, message), the message None on
    convergence (max |Phi| <= tolerance x traction scale)."""
    hist: list[float] = []
    steps: list[float] = []
    z = system.first_touch(z, ell, k_prev)
    phi = system.residual(z, ell, k_prev)
    m3 = 3 * system.m
    scale = max(np.abs(phi).max(initial=0.0), np.abs(z[:m3]).max(initial=0.0), 1e-300)
    search = Watchdog(opt.line_search_sigma, opt.watchdog, opt.min_step)
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
        J, keep, _ = system.jacobian(z, ell, k_prev)
        dz = newton_direction(J, keep, phi)
        if isinstance(dz, str):
            msg = dz
            break
        taken = search.step(lambda v: system.residual(v, ell, k_prev), z, dz,
                            0.5 * float(phi @ phi))
        if taken is None:
            msg = "line search failed (no decrease of the residual along the Newton direction)"
            break
        z, phi, alpha = taken
        steps.append(alpha)
        it += 1
    return z, StepRecord(1.0, it, hist, msg is None, steps), msg


__all__ = ["newton", "newton_direction", "Watchdog"]
