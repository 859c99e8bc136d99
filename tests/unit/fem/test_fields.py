"""The fields of a solved finite-element body (bemcontact.fem.fields):
stresses at points, on the trace, per cell, and the volume VTU file.

The contact patch test's uniform state (p0 through a frictionless interface, rollers
on xmin and ymin: uniaxial stress σ_zz = -p0, all else 0) is exact in
linear elements, so every stress the FEM body reports matches it to the
patch test's own 1e-8 of p0 (measured <= 1e-10).
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from bemcontact import (
    ConfigError, ContactPair, ContactProblem, Displacement, ElasticBody, LinearElastic, Pressure,
    SolverOptions, box,
)
from bemcontact.output.write import OutputOptions, write_results

pytest.importorskip("skfem")
pytest.importorskip("cvxopt")

from bemcontact.fem import FiniteElementBody, box_volume  # noqa: E402

P0 = 10.0
ROLLERS = {"xmin": Displacement((0.0, None, None)), "ymin": Displacement((None, 0.0, None))}
UNIAXIAL = np.array([0.0, 0.0, -P0, 0.0, 0.0, 0.0])


@pytest.fixture(scope="module")
def solved():
    lower = FiniteElementBody(box_volume((0, 0, 0), (2, 2, 1), (5, 5, 3), "hex8", 1),
                              LinearElastic(1e4, 0.3),
                              {"zmin": Displacement((None, None, 0.0)), **ROLLERS}, name="lower")
    upper = ElasticBody(box((0, 0, 1), (2, 2, 2), (6, 6, 2)), LinearElastic(3e4, 0.2),
                        {"zmax": Pressure(P0), **ROLLERS}, name="upper")
    res = ContactProblem(lower, upper, ContactPair("zmax", "zmin", 0.0)).solve(
        SolverOptions(tolerance=1e-12))
    return res


def test_stresses_at_points_on_the_trace_and_per_cell_are_the_uniform_state(solved):
    pts = np.array([[0.3, 0.4, 0.5], [1.9, 1.1, 0.95], [1.0, 1.0, 0.01]])
    assert np.abs(solved.stresses("lower", pts) - UNIAXIAL).max() <= 1e-8 * P0
    surf = solved.surface_stresses("lower")
    assert surf.shape == (solved.bodies[0].points.shape[0], 6)
    assert np.abs(surf - UNIAXIAL).max() <= 1e-8 * P0


def test_a_stress_point_outside_the_body_is_one_line(solved):
    with pytest.raises(ConfigError, match="lower: a stress point lies outside"):
        solved.stresses("lower", [[1.0, 1.0, 1.5]])


def test_the_volume_file_holds_displacement_and_stress(solved, tmp_path):
    meshio = pytest.importorskip("meshio")
    files = write_results(solved, tmp_path / "out", options=OutputOptions(figures=False))
    assert tmp_path / "out" / "lower_volume.vtu" in files
    assert not (tmp_path / "out" / "upper_volume.vtu").exists()  # a BEM body has no volume
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert summary["volume_regions"] == {"lower": ["body"]}
    m = meshio.read(tmp_path / "out" / "lower_volume.vtu")
    assert m.cells[0].type == "hexahedron" and len(m.cells[0].data) == 75
    assert np.abs(m.cell_data["stress"][0] - UNIAXIAL).max() <= 1e-8 * P0
    assert np.allclose(m.cell_data["von_mises"][0], P0, rtol=1e-8)
    # the displacement at the vertices: uniaxial strain -p0/E along z
    u = m.point_data["displacement"]
    assert np.allclose(u[:, 2], -P0 / 1e4 * m.points[:, 2], rtol=0, atol=1e-10)


def test_a_condensed_fem_body_is_reused_for_other_load_values():
    """Condensed once, re-solved for twice the pressure and another friction
    coefficient (the load responses recombined, nothing factored again):
    the same answer as a fresh solve, to the Newton tolerance."""
    def problem(p, mu):
        lower = FiniteElementBody(box_volume((0, 0, 0), (2, 2, 1), (4, 4, 2), "tet4", 2),
                                  LinearElastic(1e4, 0.3),
                                  {"zmin": Displacement((0.0, 0.0, 0.0))}, name="lower")
        upper = ElasticBody(box((0, 0, 1), (2, 2, 2), (5, 5, 2)), LinearElastic(3e4, 0.2),
                            {"zmax": Pressure(p), **ROLLERS}, name="upper")
        return ContactProblem(lower, upper, ContactPair("zmax", "zmin", mu))

    opt = SolverOptions(tolerance=1e-11)
    cond = problem(P0, 0.1).condense(opt)
    again = problem(2 * P0, 0.3).solve(opt, condensed=cond)
    fresh = problem(2 * P0, 0.3).solve(opt)
    assert again.converged and again.normal_force == pytest.approx(2 * P0 * 4, rel=1e-9)
    assert again.normal_force == pytest.approx(fresh.normal_force, rel=1e-9)
    assert np.allclose(again.frame.pressure, fresh.frame.pressure, rtol=0, atol=1e-8 * P0)
    assert np.allclose(again.stresses("lower", [[1, 1, 0.5]]),
                       fresh.stresses("lower", [[1, 1, 0.5]]), rtol=0, atol=1e-8 * P0)
