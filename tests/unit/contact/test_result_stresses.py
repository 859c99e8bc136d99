"""Stresses inside the bodies of a contact solution (ContactResult.stresses).

The contact patch test (tests/validation/test_contact_patch.py): two blocks
of different materials on non-matching meshes, frictionless, rollers on
their x = 0 and y = 0 faces, a pressure p0 on top.  The exact solution is a
uniform uniaxial stress in both blocks, σzz = -p0 and every other
component 0; the boundary solution reproduces it to 1e-8 (a linear
displacement is in the element space), so the interior stresses must too,
to the interior quadrature's tolerance (1e-6 relative by default): 1e-6 p0,
including points a tenth of an element below the contact surface
(measured 3.4e-9 to 2.9e-8 p0)."""

import numpy as np
import pytest

import bemcontact as bc

P0 = 10.0
ROLLERS = {"xmin": bc.Displacement((0.0, None, None)), "ymin": bc.Displacement((None, 0.0, None))}


@pytest.fixture(scope="module")
def patch():
    lower = bc.ElasticBody(bc.box((0, 0, 0), (2, 2, 1), (7, 7, 2)), bc.LinearElastic(1e4, 0.3),
                           {"zmin": bc.Displacement((None, None, 0.0)), **ROLLERS}, name="lower")
    upper = bc.ElasticBody(bc.box((0, 0, 1), (2, 2, 2), (11, 11, 2)), bc.LinearElastic(3e4, 0.2),
                           {"zmax": bc.Pressure(P0), **ROLLERS}, name="upper")
    problem = bc.ContactProblem(lower, upper, bc.ContactPair("zmax", "zmin", 0.0))
    return problem.solve(bc.SolverOptions(tolerance=1e-12, progress=False))


@pytest.mark.parametrize("body, z", [("lower", 0.5), ("lower", 1.0 - 0.1 * 2 / 7),
                                     ("upper", 1.5), ("upper", 1.0 + 0.1 * 2 / 11)])
def test_the_patch_test_stress_is_uniform_inside_both_blocks(patch, body, z):
    x = np.array([0.31, 1.0, 1.77])
    X, Y = np.meshgrid(x, x)
    points = np.column_stack([X.ravel(), Y.ravel(), np.full(X.size, z)])
    s = patch.stresses(body, points)
    exact = np.array([0.0, 0.0, -P0, 0.0, 0.0, 0.0])
    assert s.shape == (points.shape[0], 6)
    assert np.abs(s - exact).max() <= 1e-6 * P0, np.abs(s - exact).max()


def test_bad_stress_requests_are_one_line_errors(patch):
    with pytest.raises(bc.ConfigError, match=r"unknown body 'sphere'; the bodies are \['lower', "
                                             r"'upper'\]") as info:
        patch.stresses("sphere", [[1.0, 1.0, 0.5]])
    assert info.value.location == {"body": "sphere"}
    with pytest.raises(bc.ConfigError, match="point 0"):
        patch.stresses("lower", [[1.0, 1.0, 1.5]])  # inside the other block
