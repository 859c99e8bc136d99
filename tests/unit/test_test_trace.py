"""BEMCONTACT_TEST_TRACE (tests/conftest.py): the test now running, written
to the named file; under pytest-xdist each worker has its own file."""

from __future__ import annotations

from ..conftest import pytest_runtest_logstart, trace_path


def test_a_worker_suffixes_the_trace_file_with_its_name():
    assert trace_path("/x/trace.txt", "gw0") == "/x/trace.gw0.txt"
    assert trace_path("/x/.current-test", "gw1") == "/x/.current-test.gw1"
    assert trace_path("/x/trace.txt", None) == "/x/trace.txt"
    assert trace_path("/x/trace.txt", "") == "/x/trace.txt"


def test_each_worker_and_the_controller_write_their_own_file(tmp_path, monkeypatch):
    path = tmp_path / "trace.txt"
    monkeypatch.setenv("BEMCONTACT_TEST_TRACE", str(path))
    for worker, nodeid in (("gw0", "a.py::one"), ("gw1", "b.py::two"), (None, "b.py::two")):
        if worker is None:
            monkeypatch.delenv("PYTEST_XDIST_WORKER", raising=False)
        else:
            monkeypatch.setenv("PYTEST_XDIST_WORKER", worker)
        pytest_runtest_logstart(nodeid, (nodeid.split("::")[0], None, nodeid))
    assert {p.name: p.read_text() for p in tmp_path.iterdir()} == {
        "trace.gw0.txt": "a.py::one\n", "trace.gw1.txt": "b.py::two\n",
        "trace.txt": "b.py::two\n"}


def test_without_the_variable_nothing_is_written(tmp_path, monkeypatch):
    monkeypatch.delenv("BEMCONTACT_TEST_TRACE", raising=False)
    monkeypatch.chdir(tmp_path)
    pytest_runtest_logstart("a.py::one", ("a.py", None, "one"))
    assert list(tmp_path.iterdir()) == []
