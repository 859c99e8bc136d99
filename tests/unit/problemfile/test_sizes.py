"""Sizes refused before the work (bemcontact.problemfile.sizes): ``check``
of a 200,000-element body answers in seconds with the memory needed and
available, before any frame integration (which would take a minute)."""

from __future__ import annotations

import time

import pytest

from bemcontact.cli import main
from bemcontact.contact.memory import least_body_bytes
from bemcontact.problemfile import sizes

from ..test_cli import problem


def test_check_of_a_200k_element_body_is_refused_within_10_s(tmp_path, capsys, monkeypatch):
    """The box of 6 x 183^2 = 200,934 quad4 elements: any solve holds at least
    its compressed matrix and H-LU (209 GB); with 16 GB available (fixed, so
    the test does not depend on the machine) check refuses it in one line,
    naming both numbers, well within 10 s (building the frame of such a
    body takes about a minute)."""
    monkeypatch.setattr(sizes, "machine_memory", lambda: (32e9, 16e9))
    src = problem(tmp_path)
    src.write_text(src.read_text().replace("upper = [2, 2, 2], divisions = 1",
                                           "upper = [2, 2, 2], divisions = 183", 1))
    start = time.perf_counter()
    assert main(["check", str(src)]) == 2
    elapsed = time.perf_counter() - start
    out, err = capsys.readouterr()
    need = least_body_bytes(200_936)
    assert 200e9 < need < 220e9, need
    assert out == "" and err == (
        f"bemcontact: error: {src}: body[0].mesh: 200,934 elements and 200,936 nodes: any solve "
        f"of this body needs at least {need / 1e9:,.3g} GB (estimated peak memory), more than "
        "this machine's 16.0 GB of available memory, got {'box': {'lower': [0, 0, 0], 'upper': [2, 2, 2], 'divisions': "
        "183}}; use a coarser mesh or a machine with more memory\n"), err
    assert elapsed < 10.0, elapsed


@pytest.mark.parametrize("available, code", [(1e6, 2), (1e9, 0)])
def test_the_body_size_check_uses_the_available_memory(tmp_path, capsys, monkeypatch,
                                                         available, code):
    """A body said to need 1.3 MB at least: refused with 1 MB available
    (1.25 MB allowed, the estimate's margin), accepted with 1 GB."""
    monkeypatch.setattr(sizes, "machine_memory", lambda: (2 * available, available))
    monkeypatch.setattr(sizes, "least_body_bytes", lambda nodes: 1.3e6 * nodes / 8)
    assert main(["check", str(problem(tmp_path))]) == code
    err = capsys.readouterr().err
    if code:
        assert "body[0].mesh: 6 elements and 8 nodes: any solve of this body needs at least " \
               "0.0013 GB (estimated peak memory), more than this machine's 1 MB of available memory" \
               in err, err
    else:
        assert err == ""
