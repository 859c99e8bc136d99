"""Surface stresses from the traction and the tangential derivatives of the
displacement: exact for a uniform stress state (a linear displacement lies in
every element's space), on flat and curved elements, whatever rigid rotation
is added; and converging on a non-uniform exact field."""

from __future__ import annotations

import numpy as np
import pytest

import bemcontact as bc
from bemcontact.bem.discretization import discretize
from bemcontact.bem.solution import BodySolution
from bemcontact.bem.surface_stress import surface_stresses
from bemcontact.mesh import box, shapes
from bemcontact.validation.reference import kelvin_displacement, kelvin_stress

from ...conftest import fitted_rate

STEEL = bc.LinearElastic(210e3, 0.3)
#: a general uniform stress state (xx, yy, zz, xy, yz, xz)
SIGMA = np.array([120.0, -45.0, -300.0, 35.0, -20.0, 60.0])


def _tensor(s):
    xx, yy, zz, xy, yz, xz = s
    return np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])


def _solution(mesh, u, t_of):
    disc = discretize(mesh)
    X = disc.points
    return BodySolution(X, disc.normals, u(X), t_of(X, disc.normals), disc.weights, disc.region,
                        mesh.region_names, disc)


def _uniform(mesh):
    S = _tensor(SIGMA)
    G, nu = STEEL.shear_modulus, STEEL.poisson_ratio
    E = 2 * G * (1 + nu)
    eps = ((1 + nu) * S - nu * np.trace(S) * np.eye(3)) / E
    W = np.array([[0, -2e-3, 1e-3], [2e-3, 0, -3e-3], [-1e-3, 3e-3, 0]])  # a small rotation
    return _solution(mesh, lambda X: X @ (eps + W).T + [1e-3, -2e-3, 5e-4],
                     lambda X, n: n @ S)


@pytest.mark.parametrize("make", [
    lambda: box((0, 0, 0), (1, 2, 1.5), (3, 4, 3), element_type="quad4"),
    lambda: box((0, 0, 0), (1, 2, 1.5), (3, 4, 3), element_type="quad8"),
    lambda: box((0, 0, 0), (1, 2, 1.5), (3, 4, 3), element_type="tri3"),
], ids=["quad4", "quad8", "tri3"])
def test_a_uniform_stress_is_recovered_exactly_on_flat_elements(make):
    """The linear field lies in every element's space, so the recovery is
    exact to round-off: 1e-12 of the stress, at every node, edges and corners
    (discontinuous nodes) included."""
    sol = _uniform(make())
    s = surface_stresses(sol, STEEL)
    assert np.abs(s - SIGMA).max() <= 1e-12 * np.abs(SIGMA).max()


def test_a_uniform_stress_on_a_curved_surface_converges_with_its_normal():
    """On the curved tri6 hollow sphere the traction is σ n with the true
    (radial) normal, the element's own normal at a node differs from it by
    O(h²) (quadratic geometry), and so does the recovered stress: measured
    3.6e-2, 1.3e-3, 1.6e-4 of the largest stress at mesh sizes 0.8, 0.4,
    0.2 (rate ≥ 2 asserted; the displacement part is exact)."""
    S = _tensor(SIGMA)
    G, nu = STEEL.shear_modulus, STEEL.poisson_ratio
    eps = ((1 + nu) * S - nu * np.trace(S) * np.eye(3)) / (2 * G * (1 + nu))
    errs, hs = [], (0.8, 0.4, 0.2)
    for h in hs:
        mesh = shapes.hollow_sphere(1.0, 2.0, h, order=2)

        def traction(X, _):
            r = np.linalg.norm(X, axis=1)
            return (X / r[:, None] * np.where(r > 1.5, 1.0, -1.0)[:, None]) @ S
        sol = _solution(mesh, lambda X: X @ eps.T, traction)
        errs.append(np.abs(surface_stresses(sol, STEEL) - SIGMA).max() / np.abs(SIGMA).max())
    assert all(b < a for a, b in zip(errs, errs[1:])), errs
    assert fitted_rate(hs, errs) >= 2.0, errs
    assert errs[-1] < 5e-4, errs


def test_the_kelvin_field_of_an_outside_force_converges():
    """The Kelvin field of a point force outside a cube, its exact u and
    t = σ n at the nodes: the recovered stress at the nodes of the face
    nearest to the force, on quad4. Inside the face (shared nodes: the mean
    of the four elements' constant gradients, centred) it converges at second
    order, measured 0.117, 0.034, 8.8e-3 of the face's largest stress at 4,
    8, 16 divisions; at the edge nodes (each its own element's, one-sided) at
    first order, 0.126, 0.054, 0.024."""
    src, F = np.array([0.5, 0.5, 1.6]), np.array([0.3, -0.2, 1.0])
    G, nu = STEEL.shear_modulus, STEEL.poisson_ratio
    inner, edge, hs = [], [], []
    for n in (4, 8, 16):
        mesh = box((0, 0, 0), (1, 1, 1), n, element_type="quad4")
        sol = _solution(mesh, lambda X: kelvin_displacement(X, src, F, G, nu),
                        lambda X, nn: np.einsum("pij,pj->pi", kelvin_stress(X, src, F, nu), nn))
        top = sol.nodes_of("zmax")
        s = surface_stresses(sol, STEEL)[top]
        T = kelvin_stress(sol.points[top], src, F, nu)
        exact = np.stack([T[:, 0, 0], T[:, 1, 1], T[:, 2, 2], T[:, 0, 1], T[:, 1, 2],
                          T[:, 0, 2]], axis=1)
        err = np.abs(s - exact).max(axis=1) / np.abs(exact).max()
        shared = sol.discretization.element[top] < 0
        inner.append(err[shared].max())
        edge.append(err[~shared].max())
        hs.append(1.0 / n)
    for errs, rate in ((inner, 1.8), (edge, 0.9)):
        assert all(b < a for a, b in zip(errs, errs[1:])), errs
        assert fitted_rate(hs, errs) >= rate, errs
    assert inner[-1] < 0.015 and edge[-1] < 0.04, (inner, edge)


def test_bad_arguments_are_one_line_errors():
    sol = _uniform(box((0, 0, 0), (1, 1, 1), 2))
    with pytest.raises(bc.ConfigError, match="BodySolution"):
        surface_stresses("x", STEEL)
    with pytest.raises(bc.ConfigError, match="LinearElastic"):
        surface_stresses(sol, 1.0)
