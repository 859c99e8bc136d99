"""Body forces on a finite-element body (bemcontact.fem.loads).

* The consistent nodal forces carry the exact resultant and moment of the
  field (their integrands are polynomials the element's quadrature
  integrates exactly), for gravity and a rotation, over two materials.
* A column of ν = 0 resting on a BEM block under its own weight (free in z:
  held by the contact): the contact force is the weight (equilibrium,
  round-off), the contact pressure the uniform ρ g L and the stress in the
  column the exact σ_zz = -ρ g (L - z'), a quadratic displacement that
  quadratic elements represent exactly: tolerances 1e-8 (measured
  <= 5e-11; linear hexahedra are 12.5 % off), the same whether condensed
  for the states or reused.
* A bar of ν = 0 spun about z, on rollers that leave it a 1D problem in x
  and in y: the nodal displacements are the exact cubics ρ ω² (L² x / 2 -
  x³ / 6) / E and ρ ω² y (W² - y²) / (6 E) (Galerkin's linear elements are
  exact at the nodes of a 1D problem, and a tensor mesh of hexahedra
  reduces to it exactly), to 1e-9 (measured 3e-14; linear tetrahedra, no
  tensor mesh, are 1.6 % off).
"""

from __future__ import annotations

import numpy as np
import pytest

from bemcontact import (
    ConfigError, ContactPair, ContactProblem, Displacement, ElasticBody, LinearElastic, Pressure,
    SolverOptions, box,
)

pytest.importorskip("skfem")
pytest.importorskip("cvxopt")

from bemcontact.fem import BodyForce, FiniteElementBody, box_volume  # noqa: E402
from bemcontact.fem.loads import nodal_body_forces  # noqa: E402

RHO, G = 7.85e-9, 9810.0  # steel in mm, N, s
#: the column's: a weight that strains it 1.5e-4 (steel's own, 2e-7 at this size, is
#: within round-off of the coordinates' 1e-16 times a gap's 1e9 penalty gain)
RHO_C, G_C = 1.0, 10.0
ROLLERS = {"xmin": Displacement((0.0, None, None)), "ymin": Displacement((None, 0.0, None))}


@pytest.mark.parametrize("cell, order", [("tet4", 1), ("tet4", 2), ("hex8", 2)])
def test_the_nodal_forces_carry_the_fields_resultant_and_moment(cell, order):
    vol = box_volume((0.5, -1, 0), (2.5, 1, 1), (4, 3, 2), cell, order,
                     volumes={"left": lambda c: c[:, 0] < 1.5})
    rho = {"left": 2.0, "body": 3.0}
    force = BodyForce(gravity=(1.0, -2.0, -9.0), angular_velocity=(0.3, 0.0, 2.0),
                      center=(0.1, 0.2, 0.0))
    body = FiniteElementBody(vol, LinearElastic(1.0, 0.3), density=rho, body_force=force)
    f = nodal_body_forces(body).reshape(-1, 3)
    X = body.volume.node_points
    # the exact integrals, by a fine midpoint rule on each half (the field is linear:
    # the midpoint rule of a linear field is exact; its moment, quadratic, converges)
    want_F, want_M = np.zeros(3), np.zeros(3)
    for (x0, x1), r in (((0.5, 1.5), rho["left"]), ((1.5, 2.5), rho["body"])):
        m = 40
        axes = [(np.arange(m) + 0.5) / m * (b - a) + a for a, b in ((x0, x1), (-1, 1), (0, 1))]
        P = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
        dV = (x1 - x0) * 2 * 1 / P.shape[0]
        a = r * force.acceleration(P) * dV
        want_F += a.sum(axis=0)
        want_M += np.cross(P, a).sum(axis=0)
    assert np.abs(f.sum(axis=0) - want_F).max() <= 1e-12 * np.abs(want_F).max()
    # the midpoint rule's own error on the quadratic moment: (h²/24) per direction
    assert np.abs(np.cross(X, f).sum(axis=0) - want_M).max() <= 1e-3 * np.abs(want_M).max()


def test_the_moment_is_exact_against_the_closed_form():
    """Gravity alone on one material: Σ x_a × f_a = ρ V x_c × g exactly."""
    body = FiniteElementBody(box_volume((0, 0, 0), (2, 1, 3), 3, "tet4", 2), LinearElastic(1, 0.3),
                             density=RHO, body_force=BodyForce(gravity=(0.0, 0.0, -G)))
    f = nodal_body_forces(body).reshape(-1, 3)
    X = body.volume.node_points
    V, xc, g = 6.0, np.array([1.0, 0.5, 1.5]), np.array([0.0, 0.0, -G])
    assert np.abs(f.sum(axis=0) - RHO * V * g).max() <= 1e-12 * RHO * V * G
    assert np.abs(np.cross(X, f).sum(axis=0) - RHO * V * np.cross(xc, g)).max() <= \
        1e-12 * RHO * V * G * 3


@pytest.fixture(scope="module", params=[("tet4", 2), ("hex8", 2)], ids=["tet10", "hex27"])
def column(request):
    """A 1 x 1 x 3 column (ν = 0, density RHO_C, gravity -z) resting on a BEM
    block, z free, rollers on xmin and ymin."""
    cell, order = request.param
    L, E = 3.0, 2.0e5
    col = FiniteElementBody(box_volume((0, 0, 1), (1, 1, 1 + L), (2, 2, 4), cell, order),
                            LinearElastic(E, 0.0), ROLLERS, name="column", density=RHO_C,
                            body_force=BodyForce(gravity=(0.0, 0.0, -G_C)))
    base = ElasticBody(box((0, 0, 0), (1, 1, 1), (3, 3, 3)), LinearElastic(1e5, 0.25),
                       {"zmin": Displacement((None, None, 0.0)), **ROLLERS}, name="base")
    problem = ContactProblem(base, col, ContactPair("zmax", "zmin", 0.0))
    opt = SolverOptions(tolerance=1e-12)
    return problem, opt, problem.solve(opt), L


def test_a_column_rests_on_its_weight(column):
    problem, opt, res, L = column
    weight = RHO_C * G_C * L
    assert res.converged
    assert abs(res.normal_force - weight) <= 1e-10 * weight
    for face in res.interfaces:
        assert np.abs(face.pressure - weight).max() <= 1e-8 * weight, face.body
    z = np.linspace(1.05, 1 + L - 0.05, 7)
    pts = np.column_stack([np.full(7, 0.37), np.full(7, 0.61), z])
    s = res.stresses("column", pts)
    want = np.zeros((7, 6))
    want[:, 2] = -RHO_C * G_C * (1 + L - z)
    assert np.abs(s - want).max() <= 1e-8 * weight


def test_a_reused_condensation_carries_the_body_force(column):
    problem, opt, res, L = column
    again = problem.solve(opt, condensed=problem.condense(opt))
    assert abs(again.normal_force - res.normal_force) <= 1e-10 * res.normal_force


def test_a_spun_bar_has_the_exact_nodal_displacements():
    L, W, E, w = 2.0, 1.0, 1.0e3, 50.0
    bar = FiniteElementBody(
        box_volume((0, 0, 0), (L, W, 0.5), (8, 4, 2), "hex8", 1), LinearElastic(E, 0.0),
        {"xmin": Displacement((0.0, None, None)), "ymin": Displacement((None, 0.0, None)),
         "ymax": Displacement((None, 0.0, None)), "zmin": Displacement((None, None, 0.0))},
        name="bar", density=1e-3, body_force=BodyForce(angular_velocity=(0.0, 0.0, w)))
    lid = ElasticBody(box((0, 0, 0.5), (L, W, 1.0), (4, 2, 1)), LinearElastic(1e3, 0.0),
                      {"zmax": Pressure(1.0), "xmin": Displacement((0.0, None, None)),
                       "ymin": Displacement((None, 0.0, None))}, name="lid")
    res = ContactProblem(bar, lid, ContactPair("zmax", "zmin", 0.0)).solve(
        SolverOptions(tolerance=1e-12))
    k = 1e-3 * w * w / E
    X = bar.volume.node_points
    u = res.bodies[0].volume_displacement
    ux = k * (L * L * X[:, 0] / 2 - X[:, 0] ** 3 / 6)
    uy = k * X[:, 1] * (W * W - X[:, 1] ** 2) / 6
    scale = k * L ** 3 / 3
    assert np.abs(u[:, 0] - ux).max() <= 1e-9 * scale
    assert np.abs(u[:, 1] - uy).max() <= 1e-9 * scale


def test_bad_body_forces_are_one_line():
    vol = box_volume((0, 0, 0), (1, 1, 1), 2, "hex8", 1)
    mat = LinearElastic(1.0, 0.3)
    with pytest.raises(ConfigError, match="a body force needs the density"):
        FiniteElementBody(vol, mat, body_force=BodyForce(gravity=(0, 0, -1)))
    with pytest.raises(ConfigError, match="density of 'body' must be a finite number >= 0"):
        FiniteElementBody(vol, mat, density=-1.0)
    with pytest.raises(ConfigError, match=r"BodyForce.gravity must be 3 finite numbers"):
        BodyForce(gravity=(0, 1))
    with pytest.raises(ConfigError, match="no volume region 'coat'"):
        FiniteElementBody(vol, mat, density={"coat": 1.0})
