"""One load increment of a contact solve: the generalized Newton method
from the coarse predictor's starting point, and the nodes that close during
the increment (frictionless in it by default; with friction from their
first touch on request: ``SolverOptions.closing``)."""

from __future__ import annotations

import numpy as np

from . import law
from .newton import newton


def solve_increment(system, predictor, z, ell_prev, ell, k_prev, opt, report, done, total,
                    steps_solver):
    """One load increment by Newton, from the predictor's starting point
    when there is one (and from ``z`` if Newton fails from it); with
    ``opt.closing == "first_touch"`` the nodes that closed in it are given
    friction from their first touch (:func:`_closing`).  Returns (z, the
    :class:`StepRecord`, the failure message or None, the stick reference
    the increment's states are judged against)."""
    start, coarse = z, 0
    if predictor is not None:
        start = predictor.predict(z, ell_prev, ell, k_prev, opt)
        coarse = predictor.iterations
    znew, rec, msg = newton(system, start, ell, k_prev, opt, report, done, total, steps_solver)
    if msg is not None and start is not z:
        first = rec
        znew, rec, msg = newton(system, z, ell, k_prev, opt, report, done, total, steps_solver)
        rec.iterations += first.iterations
        rec.factorizations += first.factorizations
        rec.krylov_iterations += first.krylov_iterations
    rec.coarse_iterations = coarse
    kref = k_prev
    if msg is None and opt.closing == "first_touch":
        znew, rec, msg, kref = _closing(
            system, z, znew, rec, ell_prev, ell, k_prev, opt, report, done, total,
            steps_solver)
    return znew, rec, msg, kref

def _closing(system, z0, z1, rec, ell_prev, ell, k_prev, opt, report, done, total,
             steps_solver):
    """The nodes that closed during the increment (frictionless in it:
    :meth:`InterfaceSystem.start_increment`) get their friction back
    with the stick reference at their first touch: k_t where their gap,
    on the path with the increment's starting tractions held, reaches
    zero (linear in the load fraction); then the increment is solved
    again from ``z1``.  Returns (z, record, message, the references)."""
    closing = (system.mu_nodes == 0.0) & (system.mu_base > 0.0)
    if not closing.any():
        return z1, rec, None, k_prev
    lam, _ = system.split(z1)
    k1 = system.k(z1, ell)
    state = law.contact_state(lam.reshape(-1, 3), k1, k_prev, system.mu_nodes, system.r,
                              system.r)
    sel = np.flatnonzero(closing & (state != law.OPEN))
    if not sel.size:
        return z1, rec, None, k_prev
    g0 = system.k(z0, ell_prev)[sel, 2]
    gp = system.k(z0, ell)[sel, 2]
    drop = g0 - gp
    tau = np.where(drop > 0.0, np.clip(g0 / np.where(drop > 0.0, drop, 1.0), 0.0, 1.0), 1.0)
    kref = k_prev.copy()
    kref[sel] = k_prev[sel] + tau[:, None] * (k1[sel, :2] - k_prev[sel])
    system.mu_nodes[sel] = system.mu_base[sel]
    z2, rec2, msg2 = newton(system, z1, ell, kref, opt, report, done, total, steps_solver)
    rec2.iterations += rec.iterations
    rec2.factorizations += rec.factorizations
    rec2.krylov_iterations += rec.krylov_iterations
    rec2.coarse_iterations = rec.coarse_iterations
    rec2.residual_history = rec.residual_history + rec2.residual_history
    return z2, rec2, msg2, kref


def closed_text(system, pairs, z, ell, k_prev) -> str:
    """``; closed: <pair> c/m, ...``, the closed frame nodes of each of
    ``pairs`` at ``z`` (an assembly's progress per pair; '' for one pair)."""
    if len(pairs) < 2:
        return ""
    lam, _ = system.split(z)
    state = law.contact_state(lam.reshape(-1, 3), system.k(z, ell), k_prev,
                              system.mu_nodes, system.r, system.r)
    parts = []
    for p, pair in enumerate(pairs):
        st = state[system.frames.slice(p)]
        parts.append(f"{pair.label} {int(np.count_nonzero(st))}/{st.size}")
    return "; closed: " + ", ".join(parts)


__all__ = ["closed_text", "solve_increment"]
