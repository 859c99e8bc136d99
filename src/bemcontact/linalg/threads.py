"""Thread limits for BLAS/LAPACK (OpenBLAS through NumPy and SciPy)."""

from __future__ import annotations

import contextlib

import threadpoolctl


def blas_threads(threads: int | None):
    """A context in which BLAS/LAPACK (OpenBLAS, through NumPy and SciPy)
    uses at most ``threads`` threads, so that ``threads`` bounds the LU and
    the products as it bounds the OpenMP assembly; ``None`` leaves OpenBLAS
    at its own setting (all cores, or ``OMP_NUM_THREADS`` /
    ``OPENBLAS_NUM_THREADS``)."""
    if threads is None:
        return contextlib.nullcontext()
    return threadpoolctl.threadpool_limits(limits=int(threads), user_api="blas")



def single_threaded_blas():
    """A context in which BLAS/LAPACK runs on one thread: around many small
    calls made from OpenMP threads or between compiled products, where
    OpenBLAS's own threads only add synchronization and take the cores from
    OpenMP (measured in docs/benchmarks.md)."""
    return threadpoolctl.threadpool_limits(limits=1, user_api="blas")


__all__ = ["blas_threads", "single_threaded_blas"]
