"""Thread counts (linalg/threads.py): more threads than cores are capped,
with one warning."""

import warnings

import pytest

import bemcontact as bc
from bemcontact.linalg import threads


def test_threads_beyond_the_cores_are_capped_with_a_warning(monkeypatch):
    monkeypatch.setattr(threads.os, "sched_getaffinity", lambda pid: {0, 1}, raising=False)
    assert threads.available_cores() == 2
    with pytest.warns(bc.ResourceLimitWarning, match="threads = 4096 is more than the 2 cores"):
        assert threads.usable_threads(4096) == 2
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert threads.usable_threads(2) == 2
        assert threads.usable_threads(1) == 1
        assert threads.usable_threads(None) is None


def test_cores_without_affinity(monkeypatch):
    """Where the system does not report the affinity: every core."""
    def no_affinity(pid):
        raise OSError("not supported")

    monkeypatch.setattr(threads.os, "sched_getaffinity", no_affinity, raising=False)
    monkeypatch.setattr(threads.os, "cpu_count", lambda: 8)
    assert threads.available_cores() == 8
