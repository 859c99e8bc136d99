"""A body's coarse model, factored once: the mixed system of the remainder
problem that each of its corrections solves (:mod:`.correction`), A x = B w
for the boundary values w of the prescribed-displacement dofs ``known_u``.
It depends on the body (mesh, material, quadrature: its ``model_key``) and
on which dofs its supports prescribe, not on the grid, the loads or the
friction, so a sweep's points and an assembly's grids on a shared body reuse
it."""

from __future__ import annotations

import collections
import hashlib
import threading

import numpy as np
import scipy.linalg

from ..linalg import LinearSolverOptions

#: The coarse models factored last (:func:`coarse_factor`), at most
#: :data:`KEEP_FACTORS` of them: a sweep's points, or one history's grids,
#: solve the same bodies again.
_FACTORS: collections.OrderedDict = collections.OrderedDict()
_FACTORS_LOCK = threading.Lock()
KEEP_FACTORS = 4
#: Bodies of more dofs are not kept (their B, 3N × 3N, would double the
#: memory of the factorization; 6,000 dofs: 0.29 GB each).
KEEP_DOFS = 6000


def coarse_factor(body, known_u: np.ndarray, threads: int | None = None):
    """(LU of the mixed system's matrix A, B) of ``body``'s coarse model
    with the dofs ``known_u`` prescribed (the remainder problem's
    A x = B w for boundary values w), assembled and factored once per body
    and kind of supports (keyed by the body's ``model_key`` and
    ``known_u``), kept for the :data:`KEEP_FACTORS` bodies used last;
    :func:`clear_coarse_factors` frees them."""
    key = (body.model_key(), hashlib.sha256(np.packbits(known_u).tobytes()).hexdigest())
    with _FACTORS_LOCK:
        if key in _FACTORS:
            _FACTORS.move_to_end(key)
            return _FACTORS[key]
    n = known_u.size
    A, _, B, _ = body.mixed_system(known_u, np.zeros((n, 0)), LinearSolverOptions(method="dense"),
                                   threads, border=0, dofs=np.arange(n))
    lu = scipy.linalg.lu_factor(A, overwrite_a=True, check_finite=False)
    with _FACTORS_LOCK:
        _FACTORS[key] = (lu, B)
        while len(_FACTORS) > KEEP_FACTORS:
            _FACTORS.popitem(last=False)
    return lu, B


def clear_coarse_factors() -> None:
    """Forget the kept coarse factorizations (:func:`coarse_factor`)."""
    with _FACTORS_LOCK:
        _FACTORS.clear()


def coarse_solve(body, known_u: np.ndarray, W: np.ndarray, threads: int | None = None):
    """x (3N, s) solving the body's mixed system A x = B W for the boundary
    values ``W`` (3N, s): from the kept factorization (:func:`coarse_factor`)
    for a body of at most :data:`KEEP_DOFS` dofs, else assembled against
    ``W`` alone and not kept."""
    if known_u.size <= KEEP_DOFS:
        lu, B = coarse_factor(body, known_u, threads)
        return scipy.linalg.lu_solve(lu, B @ W, check_finite=False)
    A, BW, _, _ = body.mixed_system(known_u, W, LinearSolverOptions(method="dense"), threads,
                                    border=0)
    lu = scipy.linalg.lu_factor(A, overwrite_a=True, check_finite=False)
    return scipy.linalg.lu_solve(lu, BW, check_finite=False)


__all__ = ["KEEP_DOFS", "KEEP_FACTORS", "clear_coarse_factors", "coarse_factor", "coarse_solve"]
