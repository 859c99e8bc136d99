"""Shared test helpers."""

from __future__ import annotations

import numpy as np


def weighted_relative_error(approx, exact, weights):
    """Discrete L2 relative error sqrt(Σ w |a - e|^2 / Σ w |e|^2) over nodes."""
    approx, exact = np.asarray(approx), np.asarray(exact)
    w = np.asarray(weights)[:, None]
    return float(np.sqrt((w * (approx - exact) ** 2).sum() / (w * exact**2).sum()))


def fitted_rate(h, err):
    """Slope of log(err) against log(h) (least squares over all points)."""
    return float(np.polyfit(np.log(h), np.log(err), 1)[0])


def pytest_runtest_logstart(nodeid, location):
    """With BEMCONTACT_TEST_TRACE=FILE (set by ``make test``), the test now
    running is written to FILE, so that a run the system ends (a signal: no
    report, no summary) can still name the test it was in."""
    import os

    path = os.environ.get("BEMCONTACT_TEST_TRACE")
    if path:
        with open(path, "w") as f:
            f.write(nodeid + "\n")
