"""Element integration against closed forms and high-order references.

Closed forms (flat rectangle [x1,x2]x[y1,y2] in z = 0, normal +z, point at
(x0, y0, h)):  ∫ 1/r dA and the solid angle Ω = ∫ h/r^3 dA.  Summing an
element's columns (the basis is a partition of unity) gives

    Σ_k tr G_k = (3 (3 - 4 nu) + 1) / (16 pi G (1 - nu)) ∫ 1/r dA
    Σ_k tr H_k = 3 Ω / (4 pi)          (for a point off the element)

so both the weakly singular (point on the element: polar/Duffy rule) and the
nearly singular (point close to the element: adaptive subdivision) schemes are
checked against exact numbers.  Schemes without a closed form (curved
elements, triangles, H on the element) are checked against the same scheme
at a much higher order.  The tolerance 1e-8 is the default quadrature
tolerance (QuadratureOptions.tolerance): the schemes must deliver it.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import bemcontact as bc
from bemcontact.linalg import threads as _threads
from bemcontact.bem.operators import element_influence

G_MOD, NU = 1.0, 0.3
C_TRACE = (3 * (3 - 4 * NU) + 1) / (16 * math.pi * G_MOD * (1 - NU))
HIGH = bc.QuadratureOptions(
    tolerance=1e-15, max_order=20, singular_order=40, max_angle=0.1, max_depth=20
)


def _corner_f(a, b, z):
    R = np.sqrt(a * a + b * b + z * z)
    with np.errstate(divide="ignore", invalid="ignore"):
        t1 = np.where(a == 0, 0.0, a * np.log(b + R))
        t2 = np.where(b == 0, 0.0, b * np.log(a + R))
        t3 = np.where((z == 0) | (a == 0) | (b == 0), 0.0, z * np.arctan(a * b / (z * R)))
    return t1 + t2 - t3


def _corner_omega(a, b, z):
    R = np.sqrt(a * a + b * b + z * z)
    return np.arctan(a * b / (z * R))


def _rect(f, x1, x2, y1, y2, p):
    x0, y0, h = p
    return (
        f(x2 - x0, y2 - y0, h) - f(x1 - x0, y2 - y0, h) - f(x2 - x0, y1 - y0, h)
        + f(x1 - x0, y1 - y0, h)
    )


def inv_r_integral(x1, x2, y1, y2, p):
    return _rect(_corner_f, x1, x2, y1, y2, p)


def solid_angle(x1, x2, y1, y2, p):
    return _rect(_corner_omega, x1, x2, y1, y2, p)


def square_element(element_type="quad4", size=(2.0, 1.0), discontinuous=False):
    """One flat element on [0, a] x [0, b] in z = 0 with normal +z."""
    a, b = size
    if element_type == "quad4":
        nodes = [[0, 0, 0], [a, 0, 0], [a, b, 0], [0, b, 0]]
    else:  # quad8 / quad9: straight-sided
        nodes = [[0, 0, 0], [a, 0, 0], [a, b, 0], [0, b, 0], [a / 2, 0, 0], [a, b / 2, 0],
                 [a / 2, b, 0], [0, b / 2, 0], [a / 2, b / 2, 0]]  # fmt: skip
        nodes = nodes[: 8 if element_type == "quad8" else 9]
    mesh = bc.SurfaceMesh(np.array(nodes, float), [list(range(len(nodes)))], element_type)
    opts = bc.DiscretizationOptions(fully_discontinuous=discontinuous)
    return bc.discretize(mesh, opts)


def sum_trace(M):
    k = M.shape[1] // 3
    return sum(np.trace(M[:, 3 * j : 3 * j + 3]) for j in range(k))


@pytest.mark.parametrize("element_type", ["quad4", "quad8", "quad9"])
@pytest.mark.parametrize("discontinuous", [False, True])
def test_singular_single_layer_matches_closed_form(element_type, discontinuous):
    d = square_element(element_type, discontinuous=discontinuous)
    worst = 0.0
    for k in range(d.n_points):  # point at every functional node (corner, edge, interior)
        p = d.points[k]
        H, G = element_influence(d, 0, p, G_MOD, NU, local=k)
        exact = C_TRACE * inv_r_integral(0, 2, 0, 1, p)
        worst = max(worst, abs(sum_trace(G) - exact) / abs(exact))
    assert worst < 1e-10, f"polar rule, worst relative error {worst:.2e}"


@pytest.mark.parametrize("where", ["center", "edge", "corner", "outside_corner"])
@pytest.mark.parametrize("height", [0.3, 1e-2, 1e-4])
def test_nearly_singular_matches_closed_form(where, height):
    d = square_element("quad4")
    xy = {"center": (1.0, 0.5), "edge": (1.0, 1e-3), "corner": (2e-3, 1e-3),
          "outside_corner": (-0.01, -0.02)}[where]  # fmt: skip
    p = (xy[0], xy[1], height)
    H, G = element_influence(d, 0, p, G_MOD, NU)
    exact_g = C_TRACE * inv_r_integral(0, 2, 0, 1, p)
    exact_h = 3 * solid_angle(0, 2, 0, 1, p) / (4 * math.pi)
    err_g = abs(sum_trace(G) - exact_g) / abs(exact_g)
    # H relative to the scale of its entries (the solid angle can be ~0)
    err_h = abs(sum_trace(H) - exact_h) / (3 * 2 * math.pi / (4 * math.pi))
    assert err_g < 1e-8, f"G: relative error {err_g:.2e}"
    assert err_h < 1e-8, f"H: error {err_h:.2e}"


def test_closed_forms_agree_with_brute_force():
    """The closed forms themselves, against a dense tensor Gauss rule."""
    g, w = np.polynomial.legendre.leggauss(400)
    x = 1.0 + g
    y = 0.5 + 0.5 * g
    W = np.outer(w, 0.5 * w)
    X, Y = np.meshgrid(x, y, indexing="ij")
    p = (0.7, 0.2, 0.4)
    r = np.sqrt((X - p[0]) ** 2 + (Y - p[1]) ** 2 + p[2] ** 2)
    assert (W / r).sum() == pytest.approx(inv_r_integral(0, 2, 0, 1, p), rel=1e-12)
    assert (W * p[2] / r**3).sum() == pytest.approx(solid_angle(0, 2, 0, 1, p), rel=1e-10)


def _curved_tri6():
    """A curved tri6 patch on the unit sphere (with its own discretization)."""
    v = np.array([[1, 0, 0], [0, 1, 0], [0, 0, 1]], float) * 1.0
    mids = [(v[0] + v[1]), (v[1] + v[2]), (v[2] + v[0])]
    mids = [m / np.linalg.norm(m) for m in mids]
    nodes = np.vstack([v, mids])
    mesh = bc.SurfaceMesh(nodes, [[0, 1, 2, 3, 4, 5]], "tri6")
    return mesh


@pytest.mark.parametrize("element_type", ["tri3", "tri6", "quad8"])
@pytest.mark.parametrize("local", [0, 3, "shifted"])
def test_singular_rule_against_high_order_reference(element_type, local):
    if element_type == "tri6":
        mesh = _curved_tri6()
    elif element_type == "tri3":
        mesh = bc.SurfaceMesh([[0, 0, 0], [1.5, 0.2, 0.1], [0.3, 1.0, -0.2]], [[0, 1, 2]], "tri3")
    else:
        mesh = square_element("quad8").mesh
    if element_type == "tri3" and local == 3:
        local = 1
    shifted = local == "shifted"
    d = bc.discretize(mesh, bc.DiscretizationOptions(fully_discontinuous=shifted))
    k = 0 if shifted else local
    H, G = element_influence(d, 0, d.points[k], G_MOD, NU, local=k)
    Hr, Gr = element_influence(d, 0, d.points[k], G_MOD, NU, local=k, quadrature=HIGH)
    assert np.abs(G - Gr).max() / np.abs(Gr).max() < 1e-10
    assert np.abs(H - Hr).max() / np.abs(Hr).max() < 1e-10


@pytest.mark.parametrize("element_type", ["tri3", "tri6"])
@pytest.mark.parametrize("distance", [0.2, 1e-2, 1e-4])
def test_nearly_singular_against_high_order_reference(element_type, distance):
    mesh = (
        _curved_tri6()
        if element_type == "tri6"
        else bc.SurfaceMesh([[0, 0, 0], [1.5, 0.2, 0.1], [0.3, 1.0, -0.2]], [[0, 1, 2]], "tri3")
    )
    d = bc.discretize(mesh)
    X, n, _ = mesh.map([0, 0], [[0.3, 0.3], [0.5, 0.02]])
    for x, nx in zip(X, n):
        p = x + distance * nx
        H, G = element_influence(d, 0, p, G_MOD, NU)
        Hr, Gr = element_influence(d, 0, p, G_MOD, NU, quadrature=HIGH)
        assert np.abs(G - Gr).max() / np.abs(Gr).max() < 1e-8
        assert np.abs(H - Hr).max() / np.abs(Hr).max() < 1e-8


def test_quadrature_options_validation():
    with pytest.raises(bc.ConfigError, match="tolerance"):
        bc.QuadratureOptions(tolerance=0.0)
    with pytest.raises(bc.ConfigError, match="max_order"):
        bc.QuadratureOptions(min_order=5, max_order=3)
    with pytest.raises(bc.ConfigError, match="singular_order"):
        bc.QuadratureOptions(singular_order=0)


def test_threads_give_the_same_matrices():
    """Each collocation point's rows are one thread's work, written once: 1
    and 2 threads give the same H and G (measured identical bit for bit).
    Asserted to 1e-14 of the largest entry: a race, or a row written twice or
    not at all, is of the size of the entries; the last bits stay equal only
    while every row runs the same instructions on every thread, which no
    result relies on (a solve on 1 and on 2 threads is compared to 1e-12,
    tests/unit/test_cli.py)."""
    d = bc.discretize(bc.box(divisions=2))
    H1, G1 = bc.assemble_influence(d, 1.0, 0.3, threads=1)
    H2, G2 = bc.assemble_influence(d, 1.0, 0.3, threads=2)
    for one, two in ((H1, H2), (G1, G2)):
        np.testing.assert_allclose(two, one, rtol=0, atol=1e-14 * np.abs(one).max())


def test_assemble_system_equals_the_mixed_columns_of_h_and_g():
    from bemcontact.bem.operators import assemble_system

    d = bc.discretize(bc.box((0, 0, 0), (1, 2, 1), (3, 4, 2)))
    H, G = bc.assemble_influence(d, 3.0, 0.25)
    n = 3 * d.n_points
    rng = np.random.default_rng(0)
    ku = rng.random(n) < 0.4
    W = rng.standard_normal((n, 3))
    cols = np.array([0, 5, n - 1, 17])
    A, BW, BC = assemble_system(d, 3.0, 0.25, ku, W, cols, border=2, threads=2)
    assert A.shape == (n + 2, n + 2) and A.flags.f_contiguous
    B = np.where(ku[None, :], -H, G)
    # the same element integrals in the same order (on 2 threads here, on
    # assemble_influence's default count above): equal to rounding
    np.testing.assert_allclose(A[:n, :n], np.where(ku[None, :], -G, H), rtol=0, atol=1e-14 * np.abs(H).max())
    assert not A[n:, :].any() and not A[:, n:].any()
    np.testing.assert_allclose(BW, B @ W, rtol=0, atol=1e-12 * np.abs(B @ W).max())
    np.testing.assert_allclose(BC, B[:, cols], rtol=0, atol=1e-14 * np.abs(B).max())


def test_blas_threads_bounds_openblas_inside_and_restores_it():
    import threadpoolctl

    def blas():
        return [i["num_threads"] for i in threadpoolctl.threadpool_info() if i["user_api"] == "blas"]

    before = blas()
    assert before  # NumPy/SciPy bring OpenBLAS
    with _threads.blas_threads(1):
        assert blas() == [1] * len(before)
    assert blas() == before
    with _threads.blas_threads(None):  # None: OpenBLAS's own setting
        assert blas() == before
