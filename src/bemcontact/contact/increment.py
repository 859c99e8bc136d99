"""One load increment of a contact solve: the generalized Newton method
from the coarse predictor's starting point, and the nodes that close during
the increment (frictionless in it by default; with friction from their
first touch on request: ``SolverOptions.closing``)."""

from __future__ import annotations

import numpy as np

from . import law
from .newton import newton


def solve_increment(system, predictor, z, ell_prev, ell, opt, report, done, total,
                    steps_solver):
    """One load increment by Newton, from the predictor's starting point
    when there is one (and from ``z`` if Newton fails from it); with
    ``opt.closing == "first_touch"`` the nodes that closed in it are given
    friction from their first touch (:func:`_closing`: the law's stick
    reference then holds it).  Returns (z, the :class:`StepRecord`, the
    failure message or None)."""
    start, coarse = z, 0
    if predictor is not None:
        start = predictor.predict(z, ell_prev, ell, opt)
        coarse = predictor.iterations
    znew, rec, msg = newton(system, start, ell, opt, report, done, total, steps_solver)
    if msg is not None and start is not z:
        first = rec
        znew, rec, msg = newton(system, z, ell, opt, report, done, total, steps_solver)
        rec.iterations += first.iterations
        rec.factorizations += first.factorizations
        rec.krylov_iterations += first.krylov_iterations
    rec.coarse_iterations = coarse
    if msg is None and opt.closing == "first_touch":
        znew, rec, msg = _closing(system, z, znew, rec, ell_prev, ell, opt, report, done, total,
                                  steps_solver)
    return znew, rec, msg


def _closing(system, z0, z1, rec, ell_prev, ell, opt, report, done, total, steps_solver):
    """The nodes that closed during the increment (frictionless in it:
    :meth:`InterfaceSystem.start_increment`) get their friction back
    with the stick reference at their first touch: k_t where their gap,
    on the path with the increment's starting tractions held, reaches
    zero (linear in the load fraction); then the increment is solved
    again from ``z1``.  Returns (z, record, message)."""
    law_ = system.law
    closing = (law_.mu == 0.0) & (law_.friction > 0.0)
    if not closing.any():
        return z1, rec, None
    lam, _ = system.split(z1)
    k1 = system.k(z1, ell)
    state = law_.state(lam.reshape(-1, 3), k1)
    sel = np.flatnonzero(closing & (state != law.OPEN))
    if not sel.size:
        return z1, rec, None
    g0 = system.k(z0, ell_prev)[sel, 2]
    gp = system.k(z0, ell)[sel, 2]
    drop = g0 - gp
    tau = np.where(drop > 0.0, np.clip(g0 / np.where(drop > 0.0, drop, 1.0), 0.0, 1.0), 1.0)
    k_prev = law_.reference
    kref = k_prev.copy()
    kref[sel] = k_prev[sel] + tau[:, None] * (k1[sel, :2] - k_prev[sel])
    law_.reference = kref
    law_.mu[sel] = law_.friction[sel]
    z2, rec2, msg2 = newton(system, z1, ell, opt, report, done, total, steps_solver)
    rec2.iterations += rec.iterations
    rec2.factorizations += rec.factorizations
    rec2.krylov_iterations += rec.krylov_iterations
    rec2.coarse_iterations = rec.coarse_iterations
    rec2.residual_history = rec.residual_history + rec2.residual_history
    return z2, rec2, msg2


def closed_text(system, pairs, z, ell) -> str:
    """``; closed: <pair> c/m, ...``, the closed frame nodes of each of
    ``pairs`` at ``z`` (an assembly's progress per pair; '' for one pair)."""
    if len(pairs) < 2:
        return ""
    lam, _ = system.split(z)
    state = system.law.state(lam.reshape(-1, 3), system.law_k(z, ell))
    parts = []
    for p, pair in enumerate(pairs):
        st = state[system.frames.slice(p)]
        parts.append(f"{pair.label} {int(np.count_nonzero(st))}/{st.size}")
    return "; closed: " + ", ".join(parts)


__all__ = ["closed_text", "solve_increment"]
