"""How a body's BEM system is stored and solved: dense LU, or compressed
operators (H-matrix) with H-LU or GMRES."""

from __future__ import annotations

from dataclasses import dataclass

from .._native import core
from ..errors import ConfigError
from ..settings import Key, check_settings, setting


#: Values of :attr:`LinearSolverOptions.method`.
METHODS = ("auto", "dense", "hmatrix")


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

    eps: float = setting(Key(
        "eps", "number", "relative accuracy of each compressed block and of the H-LU",
        default=1e-6, lo=0, lo_open=True, hi=1, hi_open=True))
    eta: float = setting(Key(
        "eta", "number", "admissibility parameter: a block is compressed when "
        "min(diameters) <= eta × distance", default=3.0, lo=0, lo_open=True, hi=10))
    leaf_size: int = setting(Key(
        "leaf_size", "integer", "nodes per leaf cluster (at most); larger leaves make the "
        "H-LU faster (measured 96 vs 48: 1.7x at 5,694 nodes)", default=48, lo=1))
    max_rank: int = setting(Key(
        "max_rank", "integer", "cap on a block's rank (0: none)", default=0, lo=0))
    checks: int = setting(Key(
        "checks", "integer", "random rows and columns tested when the cross approximation "
        "would stop", default=3, lo=0))
    truncation: str = setting(Key(
        "truncation", "string", "`block`: each block to eps of its own norm; `global`: to a "
        "share of eps ‖A‖", default="block", choices=("block", "global")))
    storage: str = setting(Key(
        "storage", "string", "low-rank blocks: `double`, or `mixed` (their trailing terms in "
        "single precision where the rounding fits half the block's eps: about 30 % less "
        "memory for the same accuracy)", default="mixed", choices=("double", "mixed")))

    def __post_init__(self) -> None:
        check_settings(self)

    def to_core(self):
        h = core().HParams()
        h.eps = float(self.eps)
        h.eta = float(self.eta)
        h.leaf_size = int(self.leaf_size)
        h.max_rank = int(self.max_rank)
        h.checks = int(self.checks)
        h.global_ = self.truncation == "global"
        h.mixed = self.storage == "mixed"
        return h



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

    method: str = setting(Key(
        "method", "string", "`dense`: LAPACK LU; `hmatrix`: compressed operators; `auto`: "
        "dense up to `dense_max_nodes` nodes per body", default="auto", choices=METHODS))
    dense_max_nodes: int = setting(Key(
        "dense_max_nodes", "integer", "the `auto` threshold (functional nodes per body)",
        default=6000, lo=1))
    hmatrix: HMatrixOptions = HMatrixOptions()
    tolerance: float = setting(Key(
        "tolerance", "number", "GMRES relative residual target (of the compressed system)",
        default=1e-10, lo=0, lo_open=True, hi=1, hi_open=True))
    accuracy: float = setting(Key(
        "accuracy", "number", "relative residual the solution must reach in the exact "
        "system (sampled); above it an AccuracyWarning asks for a smaller eps",
        default=1e-6, lo=0, lo_open=True, hi=1, hi_open=True))
    check_nodes: int = setting(Key(
        "check_nodes", "integer", "nodes sampled for that check (0: none)", default=20, lo=0))
    max_iterations: int = setting(Key(
        "max_iterations", "integer", "GMRES iterations at most", default=1000, lo=1))
    restart: int = setting(Key(
        "restart", "integer", "GMRES restart length", default=200, lo=1))

    def __post_init__(self) -> None:
        if not isinstance(self.hmatrix, HMatrixOptions):
            raise ConfigError(
                f"LinearSolverOptions.hmatrix must be HMatrixOptions, got "
                f"{type(self.hmatrix).__name__}"
            )
        check_settings(self)

    def use_hmatrix(self, n_points: int) -> bool:
        if self.method == "auto":
            return n_points > self.dense_max_nodes
        return self.method == "hmatrix"



__all__ = ["HMatrixOptions", "LinearSolverOptions", "METHODS"]
