"""Compressed BEM operators: a body's mixed system matrix as a hierarchical matrix.

The dense influence matrices of :func:`~bemcontact.operators.assemble_influence`
store (3N)² numbers each.  :class:`CompressedSystem` stores the mixed system
matrix A (H on traction-given columns, -G on displacement-given ones) in
hierarchical (H-matrix) form, built by the compiled core straight from the
element integrals:

* a cluster tree on the functional nodes (the 3 unknowns of a node stay
  together), split at the median of the longest side of the bounding box until
  a cluster has at most ``leaf_size`` nodes;
* standard admissibility on the bounding boxes of the nodes' element
  supports: a block (tau, sigma) is low rank when
  ``min(diam tau, diam sigma) <= eta * dist(tau, sigma)``, dense otherwise
  (near field, leaves);
* low-rank blocks by adaptive cross approximation with partial pivoting on
  ``[H | s G]`` together (one element integration gives both), pivoting by node
  and checked on random unused node rows and columns before it stops (see the
  compiled code for why scalar pivoting fails for coplanar elasticity blocks);
  each block meets ``||M - U V^T||_F <= eps ||M||_F`` up to the estimate;
* only A is kept: the companion B (b = B values) is applied during the build to
  the vectors that need it; low-rank blocks of A are recompressed (QR + SVD) to
  A's own rank;
* the diagonal 3x3 blocks of H (free term and principal value) from rigid-body
  translation, summed over the compressed rows.

A x = b is then solved by GMRES preconditioned with the LU factors of the dense
diagonal leaf blocks of A (block Jacobi); see :func:`solve_mixed`.  Details and
measurements: docs/theory.md ("Compressed operators"), docs/benchmarks.md.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np
import scipy.linalg
import scipy.sparse.linalg
import threadpoolctl

from .errors import ConfigError, ConvergenceError
from .operators import Discretization, QuadratureOptions


def _core():
    from . import _core

    return _core


@dataclass(frozen=True)
class HMatrixOptions:
    """H-matrix settings.

    Attributes
    ----------
    eps:
        Relative (Frobenius) accuracy of each low-rank block.  The error of a
        matrix-vector product is of the same order (measured 0.05–0.1 eps on
        boxes); the solution error follows it times the condition number of
        the preconditioned system.
    eta:
        Admissibility parameter: a block is approximated when the smaller
        cluster's diameter is at most ``eta`` times the clusters' distance.
    leaf_size:
        Largest number of nodes in a leaf cluster.
    max_rank:
        Cap on the rank of a block (0: none; a block that would need a larger
        rank is stored dense).
    checks:
        Random node rows and columns tested each time the cross approximation
        would stop.
    truncation:
        ``"block"``: every low-rank block to ``eps`` of its own norm.
        ``"global"``: to an absolute budget, ``eps`` times the root-mean-square
        entry of H (or G) times the square root of the block's size, so that
        the squared block errors add up to at most ``eps² ‖H‖²_F`` (the norms
        estimated from the full rows of a few sampled nodes before the build):
        blocks of small entries, far from the diagonal, keep lower ranks.
    storage:
        ``"double"``: low-rank factors in double precision.  ``"mixed"``: the
        trailing terms of each low-rank block (small singular values) in
        single precision, as many as keep their rounding error (about 2⁻²³ of
        each term's norm) within half the block's truncation budget; the
        leading terms stay in double.  About half the memory of the low-rank
        blocks, at most 1.5 ``eps`` per block in place of ``eps``.
    """

    eps: float = 1e-6
    eta: float = 3.0
    leaf_size: int = 48
    max_rank: int = 0
    checks: int = 3
    truncation: str = "block"
    storage: str = "mixed"

    def __post_init__(self) -> None:
        if self.storage not in ("double", "mixed"):
            raise ConfigError(
                f"HMatrixOptions.storage must be 'double' or 'mixed', got {self.storage!r}"
            )
        if self.truncation not in ("block", "global"):
            raise ConfigError(
                f"HMatrixOptions.truncation must be 'block' or 'global', got {self.truncation!r}"
            )
        if not (isinstance(self.eps, (int, float)) and 0 < self.eps < 1):
            raise ConfigError(f"HMatrixOptions.eps must be in (0, 1), got {self.eps!r}")
        if not (isinstance(self.eta, (int, float)) and 0 < self.eta <= 10):
            raise ConfigError(f"HMatrixOptions.eta must be in (0, 10], got {self.eta!r}")
        for name, lo in (("leaf_size", 1), ("max_rank", 0), ("checks", 0)):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, int) or v < lo:
                raise ConfigError(f"HMatrixOptions.{name} must be an integer >= {lo}, got {v!r}")

    def to_core(self):
        h = _core().HParams()
        h.eps = float(self.eps)
        h.eta = float(self.eta)
        h.leaf_size = int(self.leaf_size)
        h.max_rank = int(self.max_rank)
        h.checks = int(self.checks)
        h.global_ = self.truncation == "global"
        h.mixed = self.storage == "mixed"
        return h


def _lapack():
    from scipy.linalg import cython_lapack

    caps = cython_lapack.__pyx_capi__
    return _core().Lapack(caps["dgeqrf"], caps["dormqr"], caps["dgesvd"], caps["dgesdd"])


def _blas():
    from scipy.linalg import cython_blas, cython_lapack

    b, lp = cython_blas.__pyx_capi__, cython_lapack.__pyx_capi__
    return _core().Blas(b["dgemm"], b["dtrsm"], lp["dgetrf"], lp["dlaswp"])


class HFactor:
    """H-LU factorization of a :class:`CompressedSystem`'s A (wraps the
    compiled ``HLU``): A ≈ P L U in hierarchical-matrix arithmetic, every
    low-rank sum truncated to the relative accuracy ``eps``; :meth:`solve`
    solves A X = B for many right-hand sides at once.  With ``update = (U,
    V)`` (each (3N, r)) it factors A + U Vᵀ instead (a floating body's A is
    singular; the bordered solve uses such an update)."""

    def __init__(self, system: CompressedSystem, eps: float | None = None,
                 update: tuple[np.ndarray, np.ndarray] | None = None) -> None:
        self.eps = system.options.eps if eps is None else float(eps)
        if not (0.0 < self.eps < 1.0):
            raise ConfigError(f"HFactor: eps must be in (0, 1), got {eps!r}")
        self.n = system.n
        if update is None:
            U = V = np.zeros((self.n, 0))
        else:
            U, V = (np.ascontiguousarray(np.asarray(a, dtype=float).reshape(self.n, -1))
                    for a in update)
        # thousands of small BLAS calls: OpenBLAS's own threads only add
        # synchronization (70 % of the time in its thread server, measured)
        with threadpoolctl.threadpool_limits(limits=1, user_api="blas"):
            self._f = _core().HLU(system._h, _lapack(), _blas(), self.eps, U, V,
                                  system.threads)

    @property
    def factor_seconds(self) -> float:
        return float(self._f.factor_seconds)

    @property
    def stored_bytes(self) -> int:
        return 8 * int(self._f.stored_doubles)

    @property
    def max_rank(self) -> int:
        return int(self._f.max_rank)

    def solve(self, b: np.ndarray) -> np.ndarray:
        """A⁻¹ b for b (3N,) or (3N, k); returns a new array."""
        b = np.asarray(b, dtype=float)
        if b.shape[:1] != (self.n,) or b.ndim not in (1, 2):
            raise ConfigError(f"solve: expected shape ({self.n},) or ({self.n}, k), got {b.shape}")
        x = np.array(b.reshape(self.n, -1), dtype=float, order="C", copy=True)
        with threadpoolctl.threadpool_limits(limits=1, user_api="blas"):
            self._f.solve(x)
        return x.reshape(b.shape)


class CompressedSystem:
    """A body's mixed system matrix A in H-matrix form (wraps the compiled
    ``HMatrix``).

    A has the columns of H at traction-given dofs and of -G at
    displacement-given ones (``known_u``); the companion B (G at
    traction-given, -H at displacement-given dofs, so that b = B values) is
    applied to the columns of ``W`` while the blocks are built and never
    stored (:attr:`BW`).

    Parameters
    ----------
    disc:
        The body's :class:`~bemcontact.operators.Discretization`.
    shear_modulus, poisson_ratio:
        Material of the body.
    known_u:
        (3N,) bool: dofs with prescribed displacement (default: none, A = H).
    W:
        (3N,) or (3N, s) vectors to multiply by B (default: none).
    quadrature:
        Element integration settings (the same as the dense path's).
    options:
        :class:`HMatrixOptions`.
    threads:
        OpenMP threads for the build and the products (default: all).
    """

    def __init__(
        self,
        disc: Discretization,
        shear_modulus: float,
        poisson_ratio: float,
        known_u: np.ndarray | None = None,
        W: np.ndarray | None = None,
        quadrature: QuadratureOptions | None = None,
        options: HMatrixOptions | None = None,
        threads: int | None = None,
    ) -> None:
        self.options = options or HMatrixOptions()
        if not isinstance(self.options, HMatrixOptions):
            raise ConfigError(f"options must be HMatrixOptions, got {type(options).__name__}")
        self.threads = _core().max_threads() if threads is None else int(threads)
        if self.threads < 1:
            raise ConfigError(f"threads must be >= 1, got {threads!r}")
        self.n_points = disc.n_points
        n = 3 * disc.n_points
        ku = np.zeros(n, dtype=bool) if known_u is None else np.asarray(known_u, dtype=bool)
        if ku.shape != (n,):
            raise ConfigError(f"known_u must have shape ({n},), got {ku.shape}")
        self.known_u = ku
        w = np.zeros((n, 0)) if W is None else np.asarray(W, dtype=float)
        self._w_vector = w.ndim == 1
        w = w.reshape(n, -1) if w.size or w.ndim == 1 else w
        if w.ndim != 2 or w.shape[0] != n or not np.isfinite(w).all():
            raise ConfigError(f"W must be finite with shape ({n},) or ({n}, s), got {np.shape(W)}")
        q = (quadrature or QuadratureOptions()).to_core()
        # the blocks are recompressed with LAPACK inside OpenMP threads: keep
        # OpenBLAS single-threaded meanwhile (nested threading halved the
        # build speed, measured)
        with threadpoolctl.threadpool_limits(limits=1, user_api="blas"):
            self._h = _core().HMatrix(
                *disc.core_arrays(), disc.points, float(shear_modulus), float(poisson_ratio), q,
                self.options.to_core(), np.ascontiguousarray(ku, dtype=np.uint8),
                np.ascontiguousarray(w), _lapack(), self.threads,
            )

    # -- size
    @property
    def n(self) -> int:
        """Rows (and columns) of A: 3N."""
        return 3 * self.n_points

    @property
    def stored_bytes(self) -> int:
        """Bytes held by the blocks of A."""
        return int(self._h.stored_bytes)

    @property
    def dense_bytes(self) -> int:
        """Bytes the dense (3N)² matrix A would need."""
        return 8 * self.n * self.n

    @property
    def build_seconds(self) -> float:
        return float(self._h.build_seconds)

    @property
    def BW(self) -> np.ndarray:
        """B W, computed during the build: (3N,) or (3N, s) like W."""
        bw = self._h.bw()
        return bw[:, 0] if self._w_vector else bw

    def block_info(self) -> np.ndarray:
        """(blocks, 7) int64: tau begin, tau size, sigma begin, sigma size (in
        the cluster order, nodes), rank (-1 for dense), ACA rank before
        recompression, failed stop checks."""
        return self._h.block_info()

    def stats(self) -> dict:
        info = self.block_info()
        lr = info[:, 4] >= 0
        return {
            "blocks": int(info.shape[0]),
            "low_rank_blocks": int(lr.sum()),
            "max_rank": int(info[lr, 4].max()) if lr.any() else 0,
            "mean_rank": float(info[lr, 4].mean()) if lr.any() else 0.0,
            "mean_aca_rank": float(info[lr, 5].mean()) if lr.any() else 0.0,
            "compressed_mb": self.stored_bytes / 1e6,
            "dense_mb": self.dense_bytes / 1e6,
            "build_s": self.build_seconds,
        }

    # -- products
    def matvec(self, x: np.ndarray) -> np.ndarray:
        """A x for a vector (3N,) or a block of columns (3N, k)."""
        x = np.asarray(x, dtype=float)
        if x.shape[:1] != (self.n,) or x.ndim not in (1, 2):
            raise ConfigError(f"matvec: expected shape ({self.n},) or ({self.n}, k), got {x.shape}")
        xx = np.ascontiguousarray(x.reshape(self.n, -1))
        y = np.empty_like(xx)
        self._h.apply(xx, y, self.threads)
        return y.reshape(x.shape)

    def entries(self, rows, cols) -> tuple[np.ndarray, np.ndarray]:
        """Exact entries H[rows][:, cols] and G[rows][:, cols] from the element
        integrals (the diagonal 3x3 blocks of H from the compressed row sums)."""
        r = np.ascontiguousarray(rows, dtype=np.int64)
        c = np.ascontiguousarray(cols, dtype=np.int64)
        for name, v in (("rows", r), ("cols", c)):
            if v.ndim != 1 or (v.size and (v.min() < 0 or v.max() >= self.n)):
                raise ConfigError(f"entries: {name} must be dof indices in 0..{self.n - 1}")
        return self._h.entries(r, c)

    def exact_rows(self, nodes) -> tuple[np.ndarray, np.ndarray]:
        """Exact rows (3 per node) of A and of B, each (3 len(nodes), 3N), from
        the element integrals."""
        nodes = np.asarray(nodes, dtype=np.int64)
        rows = (3 * nodes[:, None] + np.arange(3)).ravel()
        H, G = self.entries(rows, np.arange(self.n))
        ku = self.known_u[None, :]
        return np.where(ku, -G, H), np.where(ku, -H, G)

    def residual_check(self, x: np.ndarray, values: np.ndarray, border=None, nodes: int = 20,
                       seed: int = 0) -> float:
        """Relative residual of the exact system at ``nodes`` random nodes:
        ||A_s x + C_s U - B_s values|| / ||B_s values|| (C_s the sampled rows of
        the border columns, U = x[3N:])."""
        if nodes <= 0:
            return 0.0
        rows, As, Bs = self.sampled_rows(nodes, seed)
        b = Bs @ values
        r = As @ x[: self.n] - b
        if border is not None and border.shape[1]:
            r = r + border[rows] @ x[self.n :]
        return float(np.linalg.norm(r) / max(np.linalg.norm(b), 1e-300))

    def sampled_rows(self, nodes: int, seed: int = 0) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(dof rows, A rows, B rows) of ``nodes`` random nodes, the rows
        exact (element integrals): what the accuracy checks compare with."""
        rng = np.random.default_rng(seed)
        pick = np.sort(rng.choice(self.n_points, min(nodes, self.n_points), replace=False))
        As, Bs = self.exact_rows(pick)
        return (3 * pick[:, None] + np.arange(3)).ravel(), As, Bs

    def g_columns(self, cols) -> np.ndarray:
        """Columns ``cols`` (dof indices) of G over all rows, (3N, len(cols)),
        from the element integrals (OpenMP)."""
        c = np.ascontiguousarray(cols, dtype=np.int64)
        if c.ndim != 1 or (c.size and (c.min() < 0 or c.max() >= self.n)):
            raise ConfigError(f"g_columns: cols must be dof indices in 0..{self.n - 1}")
        return self._h.g_columns(c, self.threads)

    def factor(self, eps: float | None = None, update=None) -> HFactor:
        """H-LU factorization of A (or A + U Vᵀ, ``update = (U, V)``):
        :class:`HFactor`, truncated to ``eps`` (default: ``options.eps``)."""
        return HFactor(self, eps, update)

    def diagonal_blocks(self) -> list[tuple[np.ndarray, np.ndarray]]:
        """The dense diagonal leaves of A: [(nodes (s,), A (3s, 3s))]."""
        return self._h.diagonal_blocks()


METHODS = ("auto", "dense", "hmatrix")


@dataclass(frozen=True)
class LinearSolverOptions:
    """How a body's mixed BEM system is stored and solved.

    Attributes
    ----------
    method:
        ``"dense"``: dense H and G, LAPACK LU.  ``"hmatrix"``: H-matrix
        operators (:class:`HMatrixOptions`), GMRES with a block-Jacobi
        preconditioner.  ``"auto"``: dense up to ``dense_max_nodes`` functional
        nodes, H-matrix above.
    dense_max_nodes:
        The ``"auto"`` threshold (docs/benchmarks.md has the measurements
        behind it).
    hmatrix:
        Compression settings.
    tolerance:
        GMRES relative residual target (of the compressed system).
    accuracy:
        Relative residual the solution must reach in the *exact* (uncompressed)
        system.  After the solve it is measured on ``check_nodes`` random nodes'
        exact rows (element integrals); if it is larger, an
        :class:`~bemcontact.errors.AccuracyWarning` says so and suggests a
        smaller ``hmatrix.eps``: a too loose eps gives a warning, never a
        silently wrong answer.
    check_nodes:
        Nodes sampled for that check (0: no check).
    max_iterations, restart:
        GMRES limits.
    """

    method: str = "auto"
    dense_max_nodes: int = 6000
    hmatrix: HMatrixOptions = HMatrixOptions()
    tolerance: float = 1e-10
    accuracy: float = 1e-6
    check_nodes: int = 20
    max_iterations: int = 1000
    restart: int = 200

    def __post_init__(self) -> None:
        if self.method not in METHODS:
            raise ConfigError(
                f"LinearSolverOptions.method must be one of {list(METHODS)}, got {self.method!r}"
            )
        if not isinstance(self.hmatrix, HMatrixOptions):
            raise ConfigError(
                f"LinearSolverOptions.hmatrix must be HMatrixOptions, got "
                f"{type(self.hmatrix).__name__}"
            )
        if not (isinstance(self.tolerance, (int, float)) and 0 < self.tolerance < 1):
            raise ConfigError(
                f"LinearSolverOptions.tolerance must be in (0, 1), got {self.tolerance!r}"
            )
        if not (isinstance(self.accuracy, (int, float)) and 0 < self.accuracy < 1):
            raise ConfigError(
                f"LinearSolverOptions.accuracy must be in (0, 1), got {self.accuracy!r}"
            )
        if isinstance(self.check_nodes, bool) or not isinstance(self.check_nodes, int) or (
            self.check_nodes < 0
        ):
            raise ConfigError(
                f"LinearSolverOptions.check_nodes must be an integer >= 0, got {self.check_nodes!r}"
            )
        for name in ("dense_max_nodes", "max_iterations", "restart"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, int) or v < 1:
                raise ConfigError(f"LinearSolverOptions.{name} must be an integer >= 1, got {v!r}")

    def use_hmatrix(self, n_points: int) -> bool:
        if self.method == "auto":
            return n_points > self.dense_max_nodes
        return self.method == "hmatrix"


@dataclass
class IterativeSolve:
    """Outcome of :func:`solve_mixed`: iterations, the preconditioned relative
    residual history, and seconds per stage."""

    iterations: int
    residuals: list
    timings: dict


def solve_mixed(
    op: CompressedSystem,
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
    with threadpoolctl.threadpool_limits(limits=1, user_api="blas"):
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


__all__ = ["HMatrixOptions", "LinearSolverOptions", "CompressedSystem", "IterativeSolve", "solve_mixed"]
