"""The bordered solve: a body's BEM system with extra unknowns and equations,

    [ A  C ] [x]   [b]
    [ R  0 ] [y] = [f],

A the mixed system matrix (3N x 3N: H on traction-given, -G on
displacement-given columns), C (3N, k) the columns of the extra unknowns y
(free rigid-mode amplitudes, platen translations), R (k, 3N) their equations
(zero weighted mean motion, equilibrium in the free modes, prescribed
resultants).  One abstraction, :func:`solve_bordered`, with three backends:

``"lu"``
    A dense, assembled in place with room for the border
    (:func:`~bemcontact.bem.operators.assemble_system` with ``border = k``):
    LAPACK getrf with a singularity check (gecon), getrs for many
    right-hand sides.
``"hlu"``
    A compressed (:class:`~bemcontact.bem.compressed.CompressedSystem`, or any
    operator with its ``n``, ``matvec``, ``factor``, ``sampled_rows`` and
    ``diagonal_blocks``): H-LU
    of A + C R (nonsingular when A's null space is spanned by C and R fixes
    it: a floating body), the border by a k x k capacitance system, then one
    step of iterative refinement with the compressed product (the H-LU
    truncations leave a residual of ~100 eps; one step brings it to ~1e-11,
    measured).  Many right-hand sides at once.
``"gmres"``
    A compressed: GMRES on the bordered system, preconditioned by the LU of
    A's dense diagonal leaves (block Jacobi).  One right-hand side.

With compressed operators the solution's residual in the *exact* system is
sampled on a few nodes' rows (element integrals) and an
:class:`~bemcontact.errors.AccuracyWarning` is given above
``LinearSolverOptions.accuracy``: a too loose eps gives a warning, never a
silently wrong answer.
"""

from __future__ import annotations

import math
import time
import warnings
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import scipy.linalg
import scipy.linalg.lapack
import scipy.sparse.linalg

from ..errors import AccuracyWarning, ConfigError, ConvergenceError
from .options import LinearSolverOptions
from .threads import single_threaded_blas

#: The backends of :func:`solve_bordered`.
BACKENDS = ("lu", "hlu", "gmres")


def solve_bordered(
    A,
    rhs: np.ndarray,
    cols: np.ndarray | None = None,
    rows: np.ndarray | None = None,
    f: np.ndarray | None = None,
    *,
    backend: str,
    linear: LinearSolverOptions | None = None,
    exact_rhs: Callable[[np.ndarray], np.ndarray] | None = None,
    where: str = "",
    timings: dict | None = None,
    overwrite_rhs: bool = False,
) -> tuple[np.ndarray, np.ndarray, dict]:
    """Solve the bordered system (module docstring) with ``backend``.

    ``rhs`` is (3N,) or (3N, s); ``cols`` (3N, k), ``rows`` (k, 3N) and ``f``
    (k,) or (k, s) border it (default: no border; ``f`` default zero).
    ``linear`` gives the GMRES limits and the accuracy check of the
    compressed backends; ``exact_rhs(B_rows)`` returns the right-hand side's
    rows for sampled exact rows of B (b = B W: ``lambda Bs: Bs @ W``), for
    that check.  ``where`` prefixes messages; ``timings`` receives the dense
    backend's getrf seconds as ``"factor"``.  ``overwrite_rhs``: the dense
    backend may solve in place over a Fortran-ordered ``rhs`` (no copy of a
    large block of right-hand sides; x is then a view of it).  Returns
    ``(x, y, info)``: x like ``rhs``, y (k,) or (k, s), and what the backend
    reports (method, residuals, sizes)."""
    if backend not in BACKENDS:
        raise ConfigError(f"solve_bordered: backend must be one of {BACKENDS}, got {backend!r}")
    linear = linear or LinearSolverOptions()
    b = np.asarray(rhs, dtype=float)
    k = 0 if cols is None else cols.shape[1]
    if backend == "lu":
        if not isinstance(A, np.ndarray):
            raise ConfigError("solve_bordered: the 'lu' backend needs a dense A")
        return _dense_lu(A, b, cols, rows, f, k, where, timings, overwrite_rhs)
    if isinstance(A, np.ndarray):
        raise ConfigError(f"solve_bordered: the {backend!r} backend needs compressed operators")
    n = A.n
    if backend == "hlu":
        x, y, info = _h_lu(A, b, cols, rows, f, k)
    else:
        x, it = solve_mixed(A, b, cols, rows, f, tolerance=linear.tolerance,
                            max_iterations=linear.max_iterations, restart=linear.restart,
                            where=f"{where}: " if where else "")
        x, y = x[:n], x[n:]
        info = {"method": "hmatrix", "iterations": it.iterations, "residuals": it.residuals}
    info["exact_residual"] = _exact_check(A, x, y, cols, exact_rhs, linear, where)
    return x, y, info


# --------------------------------------------------------------------------- dense LU


def _dense_lu(A, b, cols, rows, f, k, where, timings, overwrite=False):
    n = A.shape[0] - k
    if b.shape[0] != n:
        raise ConfigError(f"solve_bordered: rhs has {b.shape[0]} rows, A has {n} (+ {k} border)")
    if k:
        A[:n, n:] = cols
        A[n:, :n] = rows
        g = np.zeros((k,) + b.shape[1:]) if f is None else np.asarray(f, dtype=float)
        b = np.concatenate([b, g]) if b.ndim == 1 else np.vstack([b, g])
        overwrite = True  # b is a new array
    # columns scaled by powers of two to a largest entry in [0.5, 1): the
    # mixed matrix's -G columns scale as 1/mu, its H columns do not, so the
    # condition estimate of the singularity check would depend on the units
    # of E (E = 1e-50 read as a body free to move); exact in floating point
    # and without effect on the pivots (partial pivoting compares entries
    # within one column)
    if not A.flags.f_contiguous:
        A = np.asfortranarray(A)
    big = np.concatenate([np.abs(A[:, j : j + 512]).max(axis=0)  # no |A| copy of A
                          for j in range(0, A.shape[1], 512)])
    scale = np.ldexp(1.0, -np.frexp(np.where(big > 0, big, 1.0))[1])
    A *= scale
    lu, piv = lu_factor_checked(A, where, timings)
    sol, _ = scipy.linalg.lapack.dgetrs(lu, piv, b, overwrite_b=overwrite)
    sol *= scale[:, None] if sol.ndim == 2 else scale
    return sol[:n], sol[n:], {"method": "dense"}


def lu_factor_checked(A: np.ndarray, where: str = "", timings: dict | None = None):
    """LU factors of the Fortran-ordered A (LAPACK getrf, in place over A)
    with a singularity check (condition estimate gecon); ``timings``, if
    given, receives the getrf seconds as ``"factor"``."""
    if not A.flags.f_contiguous:
        A = np.asfortranarray(A)
    anorm = scipy.linalg.lapack.dlange("1", A)
    t0 = time.perf_counter()
    lu, piv, info = scipy.linalg.lapack.dgetrf(A, overwrite_a=True)
    if timings is not None:
        timings["factor"] = time.perf_counter() - t0
    rcond = 0.0
    if info == 0:
        rcond, _ = scipy.linalg.lapack.dgecon(lu, anorm, norm="1")
    if info != 0 or not rcond >= 1e-14:
        raise ConfigError(
            f"{where}: the linear system is singular (reciprocal condition {rcond:.2e}): "
            "the boundary conditions do not fix the body against rigid motion; prescribe "
            "displacement components that stop translation and rotation"
        )
    return lu, piv


# --------------------------------------------------------------------------- H-LU


def _h_lu(cs, rhs, cols, rows, f, k):
    t0 = time.perf_counter()
    F = cs.factor(update=(cols, rows.T) if k else None)
    t1 = time.perf_counter()
    z = F.solve(cols) if k else None
    Rz = rows @ z if k else None
    vector = rhs.ndim == 1
    B = rhs.reshape(rhs.shape[0], -1)
    g = None if f is None else np.asarray(f, dtype=float).reshape(k, -1)

    def bordered(b, g):
        """(x, y) with (A + C R) v = b and the capacitance correction: x = v -
        z y with y = (R z)⁻¹ R v (g = 0), or x = v + z (g - y), R x = g."""
        v = F.solve(b)
        if not k:
            return v, np.zeros((0, b.shape[1]))
        if g is None:
            y = np.linalg.solve(Rz, rows @ v)
            return v - z @ y, y
        beta = np.linalg.solve(Rz, g - rows @ v)
        return v + z @ beta, g - beta

    X, Y = bordered(B, g)
    r = B - cs.matvec(X) - (cols @ Y if k else 0.0)
    first = float(np.linalg.norm(r) / max(np.linalg.norm(B), 1e-300))
    dX, dY = bordered(r, None if g is None else g - rows @ X)
    X += dX
    Y += dY
    t2 = time.perf_counter()
    info = {
        "method": "hmatrix", "compressed_mb": cs.stored_bytes / 1e6,
        "factor_mb": F.stored_bytes / 1e6, "dense_mb": cs.dense_bytes / 1e6,
        "build_s": cs.build_seconds, "factor_s": t1 - t0, "solve_s": t2 - t1,
        "lu_residual": first, "max_rank": F.max_rank,
    }
    if vector:
        X, Y = X[:, 0], Y[:, 0]
    return X, Y, info


# --------------------------------------------------------------------------- accuracy


def _exact_check(cs, x, y, cols, exact_rhs, linear, where) -> float:
    """Relative residual of the exact (uncompressed) system on
    ``linear.check_nodes`` random nodes' rows, with an AccuracyWarning above
    ``linear.accuracy``."""
    nodes = linear.check_nodes
    if nodes <= 0 or exact_rhs is None:
        return 0.0
    picked, As, Bs = cs.sampled_rows(nodes)
    b = exact_rhs(Bs)
    r = As @ x - b
    if cols is not None and cols.shape[1]:
        r = r + cols[picked] @ y
    check = float(np.linalg.norm(r) / max(np.linalg.norm(b), 1e-300))
    if check > linear.accuracy:
        eps = cs.options.eps
        warnings.warn(
            f"{where}: compressed operators with eps = {eps:g}: the exact system's residual is "
            f"{check:.2e} (sampled at {nodes} nodes), above the requested accuracy "
            f"{linear.accuracy:.1e}; lower HMatrixOptions.eps (now {eps:.1e}) or use "
            "method='dense'",
            AccuracyWarning, stacklevel=4,
        )
    return check


# --------------------------------------------------------------------------- GMRES


@dataclass
class IterativeSolve:
    """Outcome of :func:`solve_mixed`: iterations, the preconditioned relative
    residual history, and seconds per stage."""

    iterations: int
    residuals: list
    timings: dict


def solve_mixed(
    op,
    rhs: np.ndarray,
    border_cols: np.ndarray | None = None,
    border_rows: np.ndarray | None = None,
    border_rhs: np.ndarray | None = None,
    *,
    tolerance: float = 1e-10,
    max_iterations: int = 1000,
    restart: int = 200,
    where: str = "",
) -> tuple[np.ndarray, IterativeSolve]:
    """Solve [[A, C], [R, 0]] [x; U] = [rhs; f] by GMRES.

    A is ``op``'s system matrix, ``rhs`` (3N,) usually ``op.BW`` for W the
    boundary values; C (3N, k) and R (k, 3N) border the system with extra
    unknowns (platen translations, free rigid modes) and their equations,
    right-hand side ``border_rhs`` (k,).  Preconditioner: LU of A's dense
    diagonal leaf blocks (block Jacobi).  Returns (x, info) with x of length
    3N + k.  Raises :class:`ConvergenceError` with the residual history if
    GMRES does not reach ``tolerance``.
    """
    t0 = time.perf_counter()
    n = op.n
    b = np.asarray(rhs, dtype=float)
    C = np.zeros((n, 0)) if border_cols is None else np.asarray(border_cols, dtype=float)
    R = np.zeros((0, n)) if border_rows is None else np.asarray(border_rows, dtype=float)
    f = np.zeros(0) if border_rhs is None else np.asarray(border_rhs, dtype=float)
    k = C.shape[1]
    if b.shape != (n,) or R.shape != (k, n) or f.shape != (k,):
        raise ConfigError("solve_mixed: rhs, border_cols, border_rows and border_rhs do not match")
    full_rhs = np.concatenate([b, f])

    def apply(z):
        z = np.asarray(z).ravel()
        y = op.matvec(z[:n])
        if k:
            y = y + C @ z[n:]
        return np.concatenate([y, R @ z[:n]])

    # block Jacobi: LU of A's diagonal leaves (their nodes are disjoint and
    # cover the body); the border unknowns are left as they are
    factors = []
    for nodes, Ab in op.diagonal_blocks():
        dofs = (3 * nodes[:, None] + np.arange(3)).ravel()
        factors.append((dofs, scipy.linalg.lu_factor(Ab, overwrite_a=True, check_finite=False)))

    def precondition(z):
        z = np.asarray(z).ravel()
        out = z.copy()
        for dofs, lu in factors:
            out[dofs] = scipy.linalg.lu_solve(lu, z[dofs], check_finite=False)
        return out

    N = n + k
    A_op = scipy.sparse.linalg.LinearOperator((N, N), matvec=apply, dtype=float)
    M_op = scipy.sparse.linalg.LinearOperator((N, N), matvec=precondition, dtype=float)
    t1 = time.perf_counter()
    history: list[float] = []
    rs = min(restart, N)
    # GMRES's own vector work is memory bound: OpenBLAS threads gain nothing
    # there, and their spinning between calls takes the cores from the
    # product's OpenMP threads (GMRES 7.3 s -> 4.8 s at 10k nodes, measured)
    with single_threaded_blas():
        x, info = scipy.sparse.linalg.gmres(
            A_op, full_rhs, rtol=tolerance, atol=0.0, restart=rs,
            maxiter=max(1, math.ceil(max_iterations / rs)), M=M_op,
            callback=lambda r: history.append(float(r)), callback_type="pr_norm",
        )
    t2 = time.perf_counter()
    res = float(np.linalg.norm(apply(x) - full_rhs) / max(np.linalg.norm(full_rhs), 1e-300))
    out = IterativeSolve(len(history), history, {"preconditioner": t1 - t0, "gmres": t2 - t1})
    if info != 0 or not res <= 100 * tolerance:
        tail = ", ".join(f"{r:.2e}" for r in history[-10:])
        raise ConvergenceError(
            f"{where}GMRES did not converge in {len(history)} iterations: relative residual "
            f"{res:.3e} > tolerance {tolerance:.1e}; last preconditioned residuals [{tail}]; "
            "raise max_iterations, or use the dense solver for this size",
            out,
        )
    return x, out




__all__ = ["solve_bordered", "lu_factor_checked", "solve_mixed", "IterativeSolve", "BACKENDS"]
