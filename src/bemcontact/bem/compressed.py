"""Compressed BEM operators: a body's mixed system matrix as a hierarchical matrix.

The dense influence matrices of :func:`~bemcontact.bem.operators.assemble_influence`
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
diagonal leaf blocks of A (block Jacobi), or factored by an H-LU
(:class:`HFactor`); see :mod:`bemcontact.linalg.bordered`.  Details and
measurements: docs/theory.md ("Compressed operators"), docs/benchmarks.md.
"""

from __future__ import annotations


import numpy as np

from .._native import core
from ..errors import ConfigError
from ..linalg.options import HMatrixOptions
from ..linalg.threads import single_threaded_blas
from .discretization import Discretization
from .operators import QuadratureOptions


def _lapack():
    from scipy.linalg import cython_lapack

    caps = cython_lapack.__pyx_capi__
    return core().Lapack(caps["dgeqrf"], caps["dormqr"], caps["dgesvd"], caps["dgesdd"])


def _blas():
    from scipy.linalg import cython_blas, cython_lapack

    b, lp = cython_blas.__pyx_capi__, cython_lapack.__pyx_capi__
    return core().Blas(b["dgemm"], b["dtrsm"], lp["dgetrf"], lp["dlaswp"])


#: Columns per call of the compiled H-matrix product in
#: :meth:`CompressedSystem.matvec` (bounds its per-thread accumulators).
MATVEC_COLUMNS = 256



#: Compressed storage as a fraction of the dense matrix against the nodes
#: per body (benchmarks/scaling.py, eps = 1e-8, mixed precision); the H-LU's
#: factors take about as much again (benchmarks/hlu_factor.py).
COMPRESSED_FRACTIONS = ((2094, 0.487), (4974, 0.264), (10014, 0.144), (20112, 0.081),
                        (49614, 0.036))


def compressed_fraction(nodes: int) -> float:
    """The measured compressed fraction of the dense matrix for a body of
    ``nodes`` nodes (:data:`COMPRESSED_FRACTIONS`, interpolated in log-log;
    below the smallest size extrapolated with slope -0.7, the largest size's
    beyond)."""
    n, f = zip(*COMPRESSED_FRACTIONS)
    x = np.log(max(nodes, 1))
    return float(min(1.0, np.exp(np.interp(x, np.log(n), np.log(f),
                                           left=np.log(f[0]) + (np.log(n[0]) - x) * 0.7,
                                           right=None))))

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
        with single_threaded_blas():
            self._f = core().HLU(system._h, _lapack(), _blas(), self.eps, U, V,
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
        with single_threaded_blas():
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
        The body's :class:`~bemcontact.bem.discretization.Discretization`.
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
        self.threads = core().max_threads() if threads is None else int(threads)
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
        with single_threaded_blas():
            self._h = core().HMatrix(
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
        xx = x.reshape(self.n, -1)
        y = np.empty(xx.shape)
        # in blocks of MATVEC_COLUMNS: the product keeps a 3N x k accumulator
        # per thread, which for thousands of columns leaves the caches and
        # the memory's reach (4,096 columns at 2,694 nodes: 27.7 s whole,
        # 14.5 s in blocks of 256, the same product to 1e-14, measured)
        for s in range(0, xx.shape[1], MATVEC_COLUMNS):
            block = np.ascontiguousarray(xx[:, s : s + MATVEC_COLUMNS])
            out = np.empty_like(block)
            self._h.apply(block, out, self.threads)
            y[:, s : s + MATVEC_COLUMNS] = out
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


__all__ = ["CompressedSystem", "HFactor"]
