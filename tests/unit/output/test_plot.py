"""Figures (plot.py): radial profiles and force-displacement curves are
written atomically as PNG; bad arguments give one-line errors."""

from __future__ import annotations

import numpy as np
import pytest

import bemcontact as bc
from bemcontact.output.plot import plot_force_displacement, plot_radial_profile

PNG = b"\x89PNG\r\n\x1a\n"


@pytest.fixture(scope="module")
def result():
    lower = bc.ElasticBody(
        bc.box((0, 0, 0), (2, 2, 2), 2), bc.LinearElastic(1e4, 0.3), {"zmin": bc.Fixed()},
        name="lower",
    )
    upper = bc.ElasticBody(
        bc.box((0.5, 0.5, 2), (1.5, 1.5, 3), 1), bc.LinearElastic(1e4, 0.3),
        {"zmax": bc.Displacement((0.001, 0, -0.02))}, name="upper",
    )
    return bc.ContactProblem(lower, upper, bc.ContactPair("zmax", "zmin", 0.2)).solve(
        bc.SolverOptions(threads=1)
    )


def test_radial_profile_png(result, tmp_path):
    calls = []

    def exact(r):
        calls.append(r)
        return np.full_like(r, 50.0)

    out = plot_radial_profile(result, tmp_path / "p.png", pressure=exact, traction=exact,
                              center=(1.0, 1.0), title="t")
    assert out == tmp_path / "p.png"
    assert out.read_bytes()[:8] == PNG
    assert [p.name for p in tmp_path.iterdir()] == ["p.png"]  # no temporary left
    assert len(calls) == 2 and calls[0].min() == 0.0 and calls[0].max() > 0.5
    # a FrameResult works too
    assert plot_radial_profile(result.frame, tmp_path / "q.png").read_bytes()[:8] == PNG


def test_force_displacement_png(tmp_path):
    u = np.array([0.0, 1.0, 0.5, -1.0, 0.0])
    f = np.array([0.0, 2.0, 1.0, -2.0, 0.0])
    out = plot_force_displacement(u, f, tmp_path / "loop.png", analytic=(u, f), title="loop")
    assert out.read_bytes()[:8] == PNG


@pytest.mark.parametrize(
    "call, message",
    [
        (lambda r, d: plot_radial_profile("x", d / "a.png"), "expected a ContactResult or FrameResult, got str"),
        (lambda r, d: plot_radial_profile(r, d / "a.png", component=2), "component must be 0 or 1"),
        (lambda r, d: plot_radial_profile(r, d / "missing" / "a.png"), "does not exist"),
        (lambda r, d: plot_force_displacement([0, 1], [0], d / "a.png"), "got 2 and 1"),
    ],
)
def test_bad_arguments(result, tmp_path, call, message):
    with pytest.raises(bc.ConfigError, match=message):
        call(result, tmp_path)
    assert list(tmp_path.iterdir()) == []
