"""H-LU factorization of the compressed system matrix and the contact
condensation with compressed operators: the same contact solutions as the
dense path."""

from __future__ import annotations

import numpy as np
import pytest

import bemcontact as bc
from bemcontact.bem import CompressedSystem
from bemcontact.linalg import HMatrixOptions, LinearSolverOptions


def mixed_cube(divisions):
    body = bc.ElasticBody(
        bc.box((0, 0, 0), (1, 1, 1), divisions), bc.LinearElastic(1e4, 0.3),
        {"zmin": bc.Fixed(), "zmax": bc.Displacement((0, 0, -0.01))},
    )
    known_u = body.boundary_data(body.boundary_conditions)[0]
    return body, known_u


@pytest.fixture(scope="module")
def cube():
    body, ku = mixed_cube(8)
    m = body.material
    cs = CompressedSystem(body.discretization, m.shear_modulus, m.poisson_ratio, ku,
                          quadrature=body.quadrature,
                          options=HMatrixOptions(eps=1e-8, leaf_size=12), threads=2)
    return cs


def test_hlu_solves_the_compressed_system(cube):
    """A x = b for the compressed A: the H-LU alone leaves a residual of a
    few hundred eps (truncations of the Schur-complement updates; measured
    5e-7 here at eps = 1e-8; asserted 1e3 eps), one step of iterative
    refinement with the compressed product brings it to rounding (asserted
    1e-10; measured 1e-12)."""
    info = cube.block_info()
    assert (info[:, 4] > 0).sum() >= 5  # there are low-rank blocks to factor (7)
    f = cube.factor()
    assert f.max_rank > 0
    b = np.random.default_rng(1).standard_normal((cube.n, 4))
    x = f.solve(b)
    r = b - cube.matvec(x)
    first = np.linalg.norm(r) / np.linalg.norm(b)
    assert first <= 1e3 * 1e-8
    x2 = x + f.solve(r)
    assert np.linalg.norm(b - cube.matvec(x2)) / np.linalg.norm(b) <= 1e-10
    # a vector right-hand side gives the first column
    np.testing.assert_allclose(f.solve(b[:, 0]), x[:, 0], rtol=0, atol=1e-14 * np.abs(x).max())


def test_a_loose_factor_truncates_the_blocks_and_still_converges(cube):
    """factor(eps=1e-2) truncates the blocks (stored to 1e-8) to its own eps
    before the factorization: its ranks are a fraction of the tight
    factor's (measured 9 vs 65), and iterative refinement with the exact
    compressed product converges (a contraction: first residual 1.8e-3,
    then about two digits per step; asserted 1e-8 after 4 steps, measured
    8e-12)."""
    tight = cube.factor()
    loose = cube.factor(eps=1e-2)
    assert 0 < loose.max_rank < tight.max_rank / 2
    b = np.random.default_rng(3).standard_normal(cube.n)
    x = loose.solve(b)
    first = np.linalg.norm(b - cube.matvec(x)) / np.linalg.norm(b)
    assert 1e-5 < first < 1e-1  # loose, but a contraction
    for _ in range(4):
        x = x + loose.solve(b - cube.matvec(x))
    assert np.linalg.norm(b - cube.matvec(x)) / np.linalg.norm(b) <= 1e-8


def test_hlu_of_a_low_rank_update(cube):
    """factor(update=(U, V)) factors A + U Vᵀ: checked by its residual
    after one refinement step with the updated product (1e-10, as above),
    for an update of the size of the floating bodies' Rf C."""
    rng = np.random.default_rng(2)
    U = rng.standard_normal((cube.n, 2))
    V = 1e-3 * rng.standard_normal((cube.n, 2)) / cube.n
    f = cube.factor(update=(U, V))
    b = rng.standard_normal(cube.n)
    x = f.solve(b)
    r = b - cube.matvec(x) - U @ (V.T @ x)
    x = x + f.solve(r)
    r = b - cube.matvec(x) - U @ (V.T @ x)
    assert np.linalg.norm(r) / np.linalg.norm(b) <= 1e-10


def two_cubes(linear, k=8):
    lower = bc.ElasticBody(bc.box((0, 0, 0), (2, 2, 2), k), bc.LinearElastic(1e4, 0.3),
                           {"zmin": bc.Fixed()}, name="lower")
    upper = bc.ElasticBody(bc.box((0, 0, 2), (2, 2, 4), k - 1), bc.LinearElastic(1e8, 0.3),
                           {"zmax": bc.Displacement((0, 0, -0.04))}, name="upper")
    return bc.ContactProblem(lower, upper, bc.ContactPair("zmax", "zmin", 0.1)).solve(
        bc.SolverOptions(threads=2, linear=linear)
    )


COMPRESSED = LinearSolverOptions(method="hmatrix", hmatrix=HMatrixOptions(eps=1e-8, leaf_size=8))


def test_two_cubes_dense_and_compressed_agree():
    """The same contact solution from the dense and the compressed path to
    1e-6 relative (eps = 1e-8 blocks and H-LU; measured 5e-9 in the
    pressures).  The frictional, slipping dissimilar cubes."""
    rd = two_cubes(LinearSolverOptions(method="dense"))
    rh = two_cubes(COMPRESSED)
    lin = rh.linear["lower"]
    assert lin["method"] == "hmatrix" and lin["max_rank"] > 0
    assert lin["exact_residual"] <= 1e-6
    assert rd.linear["lower"]["method"] == "dense"
    assert rh.normal_force == pytest.approx(rd.normal_force, rel=1e-6)
    for a, b in ((rh.frame.pressure, rd.frame.pressure),
                 (rh.frame.tangential_traction, rd.frame.tangential_traction),
                 (rh.interfaces[0].displacement, rd.interfaces[0].displacement)):
        assert np.abs(a - b).max() <= 1e-6 * np.abs(b).max()
    np.testing.assert_array_equal(rh.frame.state, rd.frame.state)


def test_floating_body_compressed_patch_test():
    """A body whose supports leave a rigid mode free (the patch test's upper
    block: pressure on top, rollers on two sides, free in z) goes through
    the bordered H-LU (A + Rf C factored): the contact pressure is the
    applied 10 MPa to 1e-6 (the compressed operators' accuracy; dense: 1e-10)."""
    lower = bc.ElasticBody(
        bc.box((0, 0, 0), (2, 2, 1), (7, 7, 2)), bc.LinearElastic(1e4, 0.3),
        {"zmin": bc.Displacement((None, None, 0.0)), "xmin": bc.Displacement((0.0, None, None)),
         "ymin": bc.Displacement((None, 0.0, None))}, name="lower")
    upper = bc.ElasticBody(
        bc.box((0, 0, 1), (2, 2, 2), (11, 11, 2)), bc.LinearElastic(3e4, 0.2),
        {"zmax": bc.Pressure(10.0), "xmin": bc.Displacement((0.0, None, None)),
         "ymin": bc.Displacement((None, 0.0, None))}, name="upper")
    r = bc.ContactProblem(lower, upper, bc.ContactPair("zmax", "zmin")).solve(
        bc.SolverOptions(tolerance=1e-12, linear=COMPRESSED)
    )
    assert r.linear["upper"]["method"] == "hmatrix"
    assert r.linear["upper"]["max_rank"] > 0
    np.testing.assert_allclose(r.frame.pressure, 10.0, rtol=1e-6)
    assert r.normal_force == pytest.approx(40.0, rel=1e-6)


def test_too_loose_eps_warns_in_the_condensation():
    """eps = 1e-3 on the two cubes: the sampled exact residual exceeds the
    requested accuracy (1e-6) and an AccuracyWarning says so (a warning,
    not a silent wrong answer); the solve still completes."""
    loose = LinearSolverOptions(method="hmatrix", accuracy=1e-6,
                                hmatrix=HMatrixOptions(eps=1e-3, leaf_size=8))
    with pytest.warns(bc.AccuracyWarning, match=r"compressed operators with eps = 0.001") as w:
        r = two_cubes(loose)
    warned = {str(x.message).split(":")[0] for x in w}
    for name, lin in r.linear.items():  # a warning exactly for the bodies above the accuracy
        assert (name in warned) == (lin["exact_residual"] > 1e-6), (name, lin)
    assert warned
