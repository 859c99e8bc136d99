"""Fields the discretization represents exactly: rigid motion and uniform stress.

With isoparametric elements a displacement field linear in x lies in the
element space (also on distorted and curved-parametrized elements), and its
constant stress gives tractions constant on each face, also in the space.  The
only error left is quadrature (default tolerance 1e-8 per integral) and
round-off, so the thresholds (1e-10 for rigid motion, 1e-8 for uniform
stress) test the integration, the rigid-body diagonal
and the edge/corner treatment.  Measured: rigid ~1e-12, uniform <= 2e-9.
"""

from __future__ import annotations

import numpy as np
import pytest

import bemcontact as bc

pytestmark = pytest.mark.validation

E, NU = 1.0e4, 0.3
MAT = bc.LinearElastic(E, NU)
LOWER, UPPER = np.array([0.0, 0.0, 0.0]), np.array([1.0, 1.5, 2.0])
ELEMENTS = ["quad4", "tri3", "quad8", "quad9", "tri6"]


def distorted_box(element_type, divisions=3, amplitude=0.25, seed=0):
    """A box whose face-interior corner nodes are moved randomly within their
    face plane by up to ``amplitude`` x the spacing; quadratic elements keep
    straight sides (midside nodes at edge midpoints, centre nodes at the
    bilinear centre).  Quadrilaterals become non-rectangular (non-affine),
    the surface stays the box."""
    m = bc.box(LOWER, UPPER, divisions, element_type)
    X = m.nodes.copy()
    rng = np.random.default_rng(seed)
    on_bound = np.isclose(X, LOWER) | np.isclose(X, UPPER)
    face_interior = on_bound.sum(axis=1) == 1
    h = (UPPER - LOWER) / divisions
    move = rng.uniform(-1, 1, X.shape) * amplitude * h
    move[on_bound] = 0.0
    nc = 3 if element_type.startswith("tri") else 4
    corner = np.zeros(len(X), dtype=bool)
    corner[m.elements[:, :nc].ravel()] = True
    X[face_interior & corner] += move[face_interior & corner]
    E = m.elements
    if m.order == 2:
        for k in range(nc):  # midside node k between corners k and k+1
            a, b = E[:, k], E[:, (k + 1) % nc]
            X[E[:, nc + k]] = 0.5 * (X[a] + X[b])
        if element_type == "quad9":
            X[E[:, 8]] = X[E[:, :4]].mean(axis=1)
    return bc.SurfaceMesh(X, E, element_type, m.regions, source="distorted box")


def linear_field():
    A = np.array([[1e-3, 2e-4, -3e-4], [5e-4, -2e-3, 1e-4], [2e-4, 3e-4, 1.5e-3]])
    c = np.array([1e-3, -2e-3, 3e-3])
    eps = 0.5 * (A + A.T)
    lam = E * NU / ((1 + NU) * (1 - 2 * NU))
    sigma = lam * np.trace(eps) * np.eye(3) + 2 * MAT.shear_modulus * eps
    return (lambda X: X @ A.T + c), sigma


@pytest.mark.parametrize("element_type", ELEMENTS)
def test_rigid_translation_and_rotation_give_zero_traction(element_type):
    m = bc.box(LOWER, UPPER, 2, element_type)
    L = np.linalg.norm(UPPER - LOWER)
    omega = np.array([1e-3, -2e-3, 5e-4])
    shift = np.array([1e-3, 2e-3, -1e-3])
    for u in (lambda X: 0 * X + shift, lambda X: np.cross(omega, X - 0.3) + shift):
        sol = bc.ElasticBody(m, MAT, {r: bc.Displacement(u) for r in m.region_names}).solve()
        scale = E * np.abs(sol.displacement).max() / L
        err = np.abs(sol.traction).max() / scale
        assert err < 1e-10, f"{element_type}: traction {err:.2e} x E|u|/L"


@pytest.mark.parametrize("element_type", ELEMENTS)
@pytest.mark.parametrize("distorted", [False, True])
def test_linear_displacement_gives_exact_uniform_stress(element_type, distorted):
    m = distorted_box(element_type) if distorted else bc.box(LOWER, UPPER, 2, element_type)
    u, sigma = linear_field()
    sol = bc.ElasticBody(m, MAT, {r: bc.Displacement(u) for r in m.region_names}).solve()
    exact = sol.normals @ sigma
    err = np.abs(sol.traction - exact).max() / np.abs(sigma).max()
    assert err < 1e-8, f"{element_type}{' distorted' if distorted else ''}: {err:.2e}"


@pytest.mark.parametrize("element_type", ELEMENTS)
@pytest.mark.parametrize("distorted", [False, True])
def test_uniaxial_traction_block_with_minimal_supports(element_type, distorted):
    """Traction s on xmax; rollers on xmin, ymin, zmin (one component each);
    everything else traction free.  Exact: u = s/E (x, -nu y, -nu z)."""
    m = distorted_box(element_type) if distorted else bc.box(LOWER, UPPER, 2, element_type)
    s = 7.0
    sol = bc.ElasticBody(
        m,
        MAT,
        {
            "xmax": bc.Traction((s, 0.0, 0.0)),
            "xmin": bc.Displacement((0.0, None, None)),
            "ymin": bc.Displacement((None, 0.0, None)),
            "zmin": bc.Displacement((None, None, 0.0)),
        },
    ).solve()
    X = sol.points
    exact_u = s / E * np.column_stack([X[:, 0], -NU * X[:, 1], -NU * X[:, 2]])
    exact_t = sol.normals @ np.diag([s, 0.0, 0.0])
    err_u = np.abs(sol.displacement - exact_u).max() / np.abs(exact_u).max()
    err_t = np.abs(sol.traction - exact_t).max() / s
    assert err_u < 1e-8, f"displacement {err_u:.2e}"
    assert err_t < 1e-8, f"traction {err_t:.2e}"
    assert sol.reaction("xmin")[0] == pytest.approx(-s * 1.5 * 2.0, rel=1e-8)
