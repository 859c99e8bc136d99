"""Thread limits for BLAS/LAPACK (OpenBLAS through NumPy and SciPy), and
the thread count a solve may use."""

from __future__ import annotations

import contextlib
import os
import warnings

import threadpoolctl

from ..errors import ResourceLimitWarning


def available_cores() -> int:
    """The cores this process may run on (its CPU affinity where the system
    reports it, else every core)."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except (AttributeError, OSError):
        return max(1, os.cpu_count() or 1)


def usable_threads(threads: int | None) -> int | None:
    """``threads`` capped at :func:`available_cores`, with a
    :class:`~bemcontact.errors.ResourceLimitWarning` when it is more: more
    threads than cores only take turns on them (threads = 4096 ran a solve
    18x slower on 2 cores), and a problem file written on a larger machine
    should still run here.  ``None`` (all cores) stays ``None``."""
    if threads is None:
        return None
    cores = available_cores()
    if threads > cores:
        warnings.warn(
            f"threads = {threads} is more than the {cores} cores available: using {cores} "
            "(more threads than cores only slow the run down)",
            ResourceLimitWarning, stacklevel=3,
        )
        return cores
    return int(threads)


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


__all__ = ["available_cores", "blas_threads", "single_threaded_blas", "usable_threads"]
