"""Shared test helpers."""

from __future__ import annotations

import pathlib

import numpy as np


def weighted_relative_error(approx, exact, weights):
    """Discrete L2 relative error sqrt(Σ w |a - e|^2 / Σ w |e|^2) over nodes."""
    approx, exact = np.asarray(approx), np.asarray(exact)
    w = np.asarray(weights)[:, None]
    return float(np.sqrt((w * (approx - exact) ** 2).sum() / (w * exact**2).sum()))


def fitted_rate(h, err):
    """Slope of log(err) against log(h) (least squares over all points)."""
    return float(np.polyfit(np.log(h), np.log(err), 1)[0])


def trace_path(path: str, worker: str | None) -> str:
    """Where BEMCONTACT_TEST_TRACE=``path`` is written in the pytest-xdist
    worker ``worker`` (PYTEST_XDIST_WORKER, e.g. ``gw0``; None: not a worker):
    ``trace.txt`` -> ``trace.gw0.txt``, ``.current-test`` -> ``.current-test.gw0``."""
    if not worker:
        return path
    p = pathlib.Path(path)
    return str(p.with_name(f"{p.stem}.{worker}{p.suffix}"))


def pytest_runtest_logstart(nodeid, location):
    """With BEMCONTACT_TEST_TRACE=FILE (set by ``make test``), the test now
    running is written to FILE, so that a run the system ends (a signal: no
    report, no summary) can still name the test it was in.  Under
    pytest-xdist each worker writes its own file, FILE suffixed with its name
    (:func:`trace_path`: FILE.gw0, ...; two workers writing one file could
    leave it empty or mixed), and the controller, which hears of every test
    a worker starts, writes FILE itself (the latest started in any worker)."""
    import os

    path = os.environ.get("BEMCONTACT_TEST_TRACE")
    if path:
        with open(trace_path(path, os.environ.get("PYTEST_XDIST_WORKER")), "w") as f:
            f.write(nodeid + "\n")
