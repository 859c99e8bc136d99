"""Linear algebra of the bodies' systems: the linear-solver and H-matrix
options, the bordered solve with its dense-LU / H-LU / GMRES backends, and
BLAS thread limits.  (The compressed operators themselves are the body's:
:mod:`bemcontact.bem.compressed`.)"""

from .bordered import IterativeSolve, solve_bordered, solve_mixed
from .options import HMatrixOptions, LinearSolverOptions
from .threads import blas_threads, single_threaded_blas

__all__ = [
    "HMatrixOptions", "LinearSolverOptions", "IterativeSolve", "solve_bordered", "solve_mixed",
    "blas_threads", "single_threaded_blas",
]
