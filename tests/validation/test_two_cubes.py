"""The founding paper's two cubes (validation.md, "The founding paper's two cubes").

Lower cube [0,2]^2 x [0,2] (n^3 quad4 elements), upper cube [0,2]^2 x [2,4]
((n-1)^3 elements, so the interface meshes never match), E1 = 1e4 MPa,
nu = 0.3, mu = 0.1; lower face z = 0 fixed, upper face z = 4 moved by
(0, 0, -0.04) mm.

* Similar (E2 = E1): mirror symmetry about z = 2 makes the interface shear
  vanish, so nothing slips and the pair is one 2 x 2 x 4 column.
* Dissimilar (E2 = 1e8): the stiff upper cube holds its face from expanding,
  mu = 0.1 cannot, the bodies slip over (nearly) the whole interface.

Tiers, each with its reason:
1. converged, in a handful of Newton iterations;
2. invariants of every solve (frame equilibrium and complementarity to
   round-off, see ``assert_invariants``);
3. physics at the discretization tolerance measured below.
"""

from __future__ import annotations

import numpy as np
import pytest

from bemcontact import (
    ContactPair,
    ContactProblem,
    ConvergenceError,
    Displacement,
    ElasticBody,
    LinearElastic,
    SolverOptions,
    box,
)

pytestmark = pytest.mark.validation

MU = 0.1
E1 = 1.0e4
DELTA = 0.04


def bodies(n, E2, top=(0.0, 0.0, -DELTA)):
    lower = ElasticBody(
        box((0, 0, 0), (2, 2, 2), n), LinearElastic(E1, 0.3),
        {"zmin": Displacement((0.0, 0.0, 0.0))}, name="lower",
    )
    upper = ElasticBody(
        box((0, 0, 2), (2, 2, 4), n - 1), LinearElastic(E2, 0.3),
        {"zmax": Displacement(top)}, name="upper",
    )
    return lower, upper


def solve(n, E2, mu=MU, penalty=1.0, swap=False):
    lower, upper = bodies(n, E2)
    if swap:
        problem = ContactProblem(upper, lower, ContactPair("zmin", "zmax", mu))
    else:
        problem = ContactProblem(lower, upper, ContactPair("zmax", "zmin", mu))
    res = problem.solve(SolverOptions(penalty=penalty))
    assert_invariants(res, mu)
    return res


def assert_invariants(res, mu):
    """What every converged contact solve must satisfy.

    Tight (round-off / Newton tolerance 1e-10, asserted at 1e-8 relative):
    the interface forces of the two bodies (their contact-surface reactions)
    balance each other and equal the frame force; at the frame nodes (the
    unknowns of the law) p >= 0, weighted gap >= 0, p * gap = 0 and
    |t_t| <= mu p.
    Discretization level (documented in docs/validation.md): whole-body
    equilibrium (collocation BEM enforces sum of tractions = 0 only
    approximately, measured 1e-4 to 1.1e-3), pointwise gaps at body nodes
    between non-matching surfaces, and the cone on the body that does not own
    the frame (its tractions are an L2 projection; measured <= 0.9 % of p_max).
    """
    assert res.converged
    fr = res.frame
    act = fr.weights > 0
    F = res.normal_force
    pmax = fr.pressure.max()
    r1 = res.bodies[0].reaction(res.interfaces[0].surface)
    r2 = res.bodies[1].reaction(res.interfaces[1].surface)
    np.testing.assert_allclose(r1 + r2, 0, atol=1e-8 * F)
    np.testing.assert_allclose(r2, res.contact_force, atol=1e-8 * F)
    p, g = fr.pressure[act], fr.gap[act]
    u_scale = DELTA
    assert p.min() >= -1e-8 * pmax
    assert g.min() >= -1e-8 * u_scale
    assert np.abs(p * g).max() <= 1e-8 * pmax * u_scale
    tt = np.linalg.norm(fr.tangential_traction[act], axis=1)
    assert (tt - mu * p).max() <= 1e-8 * pmax
    for iface, sol in zip(res.interfaces, res.bodies):
        total = sum(sol.reactions().values())
        assert np.abs(total).max() <= 2e-3 * F, f"{iface.body}: body imbalance {total}"
        assert np.nanmin(iface.pressure) >= 0.5 * pmax  # these cases are closed everywhere
        excess = (np.linalg.norm(iface.tangential_traction, axis=1) - mu * iface.pressure).max()
        assert excess <= 0.02 * pmax, f"{iface.body}: cone exceeded by {excess / pmax:.2e} p_max"


@pytest.fixture(scope="module")
def similar():
    return {n: solve(n, E1) for n in (4, 6, 8)}


@pytest.fixture(scope="module")
def dissimilar():
    return {n: solve(n, 1.0e8) for n in (4, 5, 6, 8)}


def column_force(n):
    """The similar pair as one 2 x 2 x 4 column, one-body solver."""
    col = ElasticBody(
        box((0, 0, 0), (2, 2, 4), (n, n, 2 * n)), LinearElastic(E1, 0.3),
        {"zmin": Displacement((0.0, 0.0, 0.0)), "zmax": Displacement((0.0, 0.0, -DELTA))},
    )
    return -col.solve().reaction("zmax")[2]


def test_similar_cubes_stick_everywhere(similar):
    for n, res in similar.items():
        assert res.newton_iterations <= 3, (n, res.steps[0].residual_history)
        assert res.frame.counts() == {"open": 0, "stick": res.frame.state.size, "slip": 0}
        # the mirror symmetry leaves no shear: |F_t| is round-off (measured <= 6e-11 N)
        assert res.tangential_force <= 1e-8 * res.normal_force
    # u_y (and u_x) of the two bodies coincide: the pointwise relative
    # displacement is pure discretization error of the weak (mortar) tie,
    # measured 9.6e-6, 4.4e-6, 2.1e-6 mm (|u_y| ~ 3e-3 mm) and falling ~h^2
    slips = [np.nanmax(np.linalg.norm(res.interfaces[0].slip, axis=1)) for res in similar.values()]
    assert slips[0] <= 2e-5 and slips[-1] <= 4e-6
    assert slips[0] > slips[1] > slips[2]
    uy = np.abs(similar[8].interfaces[0].displacement[:, 1]).max()
    assert slips[-1] <= 2e-3 * uy


def test_similar_cubes_equal_the_column(similar):
    """Pair vs column: both are discretizations of the same solution; their
    measured difference, 0.7-1.6e-4 relative for n = 4..12, is the size of
    each one's own variation under refinement (column 412.088 / .116 / .107 /
    .096 N, pair 412.118 / .178 / .172 / .155 N), so 5e-4 is three times the
    measured discretization error."""
    for n, res in similar.items():
        ref = column_force(n)
        assert 400 <= ref <= 538
        assert res.normal_force == pytest.approx(ref, rel=5e-4), (n, res.normal_force, ref)


def test_dissimilar_cubes_slip_nearly_everywhere(dissimilar):
    for n, res in dissimilar.items():
        assert res.newton_iterations <= 10, (n, res.steps[0].residual_history)
        fr = res.frame
        st = fr.state == 1
        # stick at most at the centre node (present when the frame has an even
        # number of elements per edge: n = 5 here), never elsewhere
        assert np.count_nonzero(fr.state == 2) >= fr.state.size - 1
        assert np.all(np.linalg.norm(fr.points[st, :2] - 1.0, axis=1) <= 1e-12)
        # slipping nodes sit on the cone and slip along the traction's opposite
        # ... traction on body 2 opposes body 2's slip relative to body 1
        sl = fr.state == 2
        tt = np.linalg.norm(fr.tangential_traction[sl], axis=1)
        np.testing.assert_allclose(tt, MU * fr.pressure[sl], rtol=1e-8)
        s = fr.slip[sl]
        cosine = np.einsum("ij,ij->i", s, fr.tangential_traction[sl]) / (
            np.linalg.norm(s, axis=1) * tt
        )
        assert cosine.max() <= -0.999
        # u_y of the two bodies differ (the paper's Figure 1b): the lower body
        # expands outward, the nearly rigid upper one hardly
        low, up = res.interfaces
        # (measured at n = 4: u_y = 3.9-4.0e-3 mm on the node row nearest y = 2,
        # |u_y| <= 8.3e-7 mm on the upper body)
        edge = low.points[:, 1] >= low.points[:, 1].max() - 1e-12
        assert low.displacement[edge, 1].min() > 2e-3
        assert np.abs(up.displacement[:, 1]).max() < 1e-2 * low.displacement[edge, 1].min()


def test_dissimilar_force_converges_within_bounds(dissimilar):
    """Measured 833.657 / 833.835 / 834.158 / 834.289 N (n = 4, 5, 6, 8; and
    834.363 at n = 12): monotone, differences contracting (ratio 0.26 between
    the 4-6-8 steps), inside the uniaxial/confined bounds of validation.md."""
    F = {n: r.normal_force for n, r in dissimilar.items()}
    assert all(800 <= f <= 1077 for f in F.values())
    assert F[4] < F[5] < F[6] < F[8]
    assert abs(F[8] - F[6]) <= 0.5 * abs(F[6] - F[4])
    assert F[8] == pytest.approx(834.29, rel=1e-4)  # regression on the recorded table


def test_dissimilar_pressure_peaks_at_the_edges(dissimilar):
    """The pressure is singular at the free edges of the interface: the frame
    pressure is largest at the corners/edges and smallest at the centre."""
    fr = dissimilar[8].frame
    r = np.linalg.norm(fr.points[:, :2] - 1.0, axis=1)
    assert fr.pressure[np.argmax(r)] == pytest.approx(fr.pressure.max())
    assert fr.pressure[np.argmin(r)] < np.median(fr.pressure)


@pytest.mark.parametrize("penalty", [0.1, 10.0])
def test_solution_does_not_depend_on_the_penalty(dissimilar, penalty):
    """The augmentation parameters change the iteration, not the solution:
    frame and body tractions agree to the Newton tolerance (measured
    3e-12..7e-12 relative to p_max)."""
    base = dissimilar[4]
    res = solve(4, 1.0e8, penalty=penalty)
    pmax = base.frame.pressure.max()
    assert res.newton_iterations <= 10
    np.testing.assert_allclose(res.frame.pressure, base.frame.pressure, atol=1e-8 * pmax)
    np.testing.assert_allclose(
        res.frame.tangential_traction, base.frame.tangential_traction, atol=1e-8 * pmax
    )
    for a, b in zip(res.interfaces, base.interfaces):
        np.testing.assert_allclose(a.traction, b.traction, atol=1e-8 * pmax)


def test_swapping_the_bodies_gives_the_same_tractions(dissimilar):
    base = dissimilar[4]
    res = solve(4, 1.0e8, swap=True)
    assert res.names == ("upper", "lower")
    pmax = base.frame.pressure.max()
    for a, b in zip(res.interfaces[::-1], base.interfaces):
        assert a.body == b.body
        np.testing.assert_allclose(a.traction, b.traction, atol=1e-8 * pmax)
        np.testing.assert_allclose(a.displacement, b.displacement, atol=1e-8 * DELTA)
    assert res.normal_force == pytest.approx(base.normal_force, rel=1e-10)


def test_unsupported_body_gives_a_clear_error_quickly():
    """Frictionless and the upper cube held only in z: it can slide and spin
    freely, so there is no solution.  The solver must say so at once."""
    lower, upper = bodies(4, E1, top=(None, None, -DELTA))
    problem = ContactProblem(lower, upper, ContactPair("zmax", "zmin", 0.0))
    with pytest.raises(ConvergenceError, match="free to move") as info:
        problem.solve()
    res = info.value.result
    assert not res.converged
    assert res.steps[-1].iterations <= 1
    assert "residual history" in str(info.value)


def test_proportional_load_steps_give_the_one_step_answer():
    """Under proportional loading every node slips monotonically in a fixed
    direction, so the answer is path independent: three load steps, each
    measuring slip from the previous converged step, must reproduce the
    one-step solution (measured 2.7e-14 p_max; asserted at the Newton
    tolerance level 1e-8).  A total-slip formulation would agree here too;
    the incremental one is what makes non-monotonic histories correct."""
    lower, upper = bodies(5, 1.0e8)
    problem = ContactProblem(lower, upper, ContactPair("zmax", "zmin", MU))
    one = problem.solve(SolverOptions(load_steps=1))
    three = problem.solve(SolverOptions(load_steps=3))
    assert_invariants(three, MU)
    assert [s.load_factor for s in three.steps] == pytest.approx([1 / 3, 2 / 3, 1])
    assert all(s.converged and s.iterations <= 10 for s in three.steps)
    assert three.newton_iterations == sum(s.iterations for s in three.steps)
    pmax = one.frame.pressure.max()
    np.testing.assert_array_equal(three.frame.state, one.frame.state)
    np.testing.assert_allclose(three.frame.pressure, one.frame.pressure, atol=1e-8 * pmax)
    np.testing.assert_allclose(
        three.frame.tangential_traction, one.frame.tangential_traction, atol=1e-8 * pmax
    )
    np.testing.assert_allclose(three.frame.slip, one.frame.slip, atol=1e-8 * DELTA)


def test_similar_cubes_stresses_equal_the_columns(similar):
    """Stresses inside both cubes on 3 x 3 x 3 points away from the edges
    (x, y in [0.5, 1.5], 0.3 to 0.7 of each cube's height): the pair's and the
    one-body column's agree to 5e-3 of the axial stress, and the difference
    falls on every refinement (measured, lower / upper cube: 6.1e-4 / 3.8e-3,
    6.5e-5 / 1.0e-3, 3.9e-5 / 4.0e-4 at n = 4, 6, 8: the upper cube has the
    coarser mesh, n - 1). The axial stress at the centres (−108.2 MPa) lies
    between the uniaxial −E ε = −100 MPa and the confined
    −E(1 − ν)/((1 + ν)(1 − 2ν)) ε = −134.6 MPa (ε = 0.04 / 4): the clamped
    ends confine the column near them, and F/A = −103.0 MPa."""
    g = np.linspace(0.5, 1.5, 3)
    X, Y, Z = np.meshgrid(g, g, [0.6, 1.0, 1.4], indexing="ij")
    lower = np.column_stack([X.ravel(), Y.ravel(), Z.ravel()])
    upper = lower + [0.0, 0.0, 2.0]
    diffs = []
    eps = DELTA / 4.0
    for n, res in similar.items():
        col = ElasticBody(
            box((0, 0, 0), (2, 2, 4), (n, n, 2 * n)), LinearElastic(E1, 0.3),
            {"zmin": Displacement((0.0, 0.0, 0.0)), "zmax": Displacement((0.0, 0.0, -DELTA))},
        )
        sol = col.solve()
        s1, s2 = res.stresses("lower", lower), res.stresses("upper", upper)
        scale = E1 * eps
        d = (np.abs(s1 - col.stresses(sol, lower)).max() / scale,
             np.abs(s2 - col.stresses(sol, upper)).max() / scale)
        assert max(d) <= 5e-3, (n, d)
        diffs.append(d)
        for s in (s1[13], s2[13]):  # the cubes' centres
            assert -E1 * 0.7 / (1.3 * 0.4) * eps < s[2] < -E1 * eps
            assert np.abs(s[3:]).max() <= 1e-3 * scale  # no shear on the axis of symmetry
    for k in range(2):
        assert all(b[k] < a[k] for a, b in zip(diffs, diffs[1:])), diffs
