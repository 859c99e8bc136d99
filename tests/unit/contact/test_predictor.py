"""The coarse-to-fine predictor (contact/predictor.py): the clusters, the
aggregated interface system as the exact restriction of the fine one for
tractions constant over each cluster, and a solve that changes nothing but
the Newton iteration counts."""

import math

import numpy as np
import pytest

import bemcontact as bc
from bemcontact.contact import law, predictor
from bemcontact.contact.predictor import Predictor, aggregated, clusters
from bemcontact.validation import cases
from bemcontact.validation.reference import contact as ref

from .test_problem import MU, P, _problem, _q, _system


def test_clusters_are_compact_groups_of_four():
    """A jittered 20 x 20 grid of unit spacing: every point in one cluster,
    2-4 points each, and each cluster within about a 2 x 2 block of cells
    (all four here: 400 is a multiple of 4) near one another: diameter at
    most that of a 1 x 4 strip (3 plus 2 x 0.1 of jitter; the count-balanced
    cuts make some, measured 3.06) and on average about that of a 2 x 3
    block (sqrt(5) = 2.24; measured 2.03)."""
    rng = np.random.default_rng(3)
    g = np.stack(np.meshgrid(np.arange(20.0), np.arange(20.0)), -1).reshape(-1, 2)
    x = np.column_stack([g + rng.uniform(-0.1, 0.1, g.shape), 0.01 * rng.standard_normal(len(g))])
    c = clusters(x)
    counts = np.bincount(c)
    assert c.shape == (400,) and counts.sum() == 400
    assert counts.min() == counts.max() == 4 and len(counts) == 100
    diam = [np.linalg.norm(x[c == k][:, None] - x[c == k][None], axis=2).max()
            for k in range(len(counts))]
    assert max(diam) <= 3.2 and np.mean(diam) <= 2.24


@pytest.fixture(scope="module")
def two_blocks():
    return _system(_problem(), [bc.LoadStep(label="P"), _q(0.5 * MU * P)])


def test_aggregated_system_restricts_the_fine_one(two_blocks):
    """For tractions constant over each cluster (z = P z_c), the coarse
    relative displacements are the area-weighted means of the fine ones
    (k_c = R k(P z_c)) and the equilibrium and resultant rows are the fine
    ones, to rounding (1e-12 of their scale); the clusters' areas add up to
    the frame's."""
    system = two_blocks
    g = clusters(system.frame.points[system.act], size=4)
    coarse = aggregated(system, g)
    assert coarse.m == g.max() + 1 < system.m
    assert math.isclose(coarse.a.sum(), system.a.sum(), rel_tol=1e-14)
    rng = np.random.default_rng(0)
    zc = rng.standard_normal(coarse.zero().size) * P / system.area
    m3, mc3 = 3 * system.m, 3 * coarse.m
    z = np.concatenate([coarse.prolongation @ zc[:mc3], zc[mc3:]])
    ell = np.array([1.0, 0.3])
    k = system.k(z, ell).ravel()
    kc = coarse.k(zc, ell).ravel()
    np.testing.assert_allclose(kc, coarse.restriction @ k, rtol=0, atol=1e-12 * np.abs(k).max())
    lam, parts = system.split(z)
    lamc, partsc = coarse.split(zc)
    for fine, agg in zip(system._rows(lam, parts, ell), coarse._rows(lamc, partsc, ell)):
        np.testing.assert_allclose(agg, fine, rtol=0, atol=1e-12 * np.abs(fine).max())
    assert coarse.restriction.shape == (mc3, m3)
    # restriction after prolongation is the identity
    np.testing.assert_allclose((coarse.restriction @ coarse.prolongation).toarray(), np.eye(mc3),
                               atol=1e-14)


def test_aggregated_checks_its_clusters(two_blocks):
    with pytest.raises(bc.ConfigError, match="cluster"):
        aggregated(two_blocks, np.zeros(3, dtype=int))


APPROACH, H = 0.03, 0.1


@pytest.fixture(scope="module")
def sphere_on_block():
    """Cattaneo–Mindlin on the steel hemisphere and block at a/h = 5.5
    (244 active frame nodes: one coarse level of 64 clusters): P, then
    Q = 0.5 mu P in two increments."""
    s = cases.SphereOnBlock(size_profile=((0.0, H), (1.1 * math.sqrt(10 * APPROACH), H)),
                            growth=0.6)
    p = ref.hertz_force(APPROACH, s.radius, s.contact_modulus)
    prob = cases.sphere_on_block(H, APPROACH, friction_coefficient=0.3, setup=s)
    steps = [bc.LoadStep(label="P")] + cases.tangential_steps([0.5 * 0.3 * p], APPROACH,
                                                              increments=2)
    return prob, steps


def test_predictor_changes_nothing_but_the_iterations(sphere_on_block):
    """With and without the predictor: the same forces to 1e-9 of the normal
    force (both converge to the Newton tolerance 1e-10 of the traction
    scale) and the same contact states at every step, in fewer Newton
    iterations on the frame (measured 15 -> 11; 3 at the normal load from
    all-open, where the first iterate closes the whole overlap disk and the
    following ones open a ring at a time: 5 without)."""
    prob, steps = sphere_on_block
    none = prob.solve(bc.SolverOptions(predictor="none"), steps=steps)
    pred = prob.solve(bc.SolverOptions(predictor="coarse"), steps=steps)
    for a, b in zip(none.history, pred.history):
        np.testing.assert_allclose(b.contact_force, a.contact_force, rtol=0,
                                   atol=1e-9 * abs(a.normal_force))
        np.testing.assert_array_equal(b.frame.state, a.frame.state)
    assert (pred.history[-1].frame.state == law.SLIP).any()
    assert all(s.coarse_iterations == 0 for s in none.steps)
    assert all(s.coarse_iterations > 0 for s in pred.steps)
    assert pred.steps[0].iterations <= none.steps[0].iterations - 2
    assert pred.newton_iterations <= none.newton_iterations - 3


def test_a_coarse_level_that_fails_is_skipped(sphere_on_block, monkeypatch):
    """When a coarse level does not converge, the fine level starts where it
    would have without the predictor: the very iterations of predictor =
    "none", the same answer."""
    prob, steps = sphere_on_block
    real = predictor.newton

    def failing(system, z, ell, opt, *args, **kw):
        znew, rec, _ = real(system, z, ell, opt, *args, **kw)
        return znew, rec, "no convergence (test)"

    monkeypatch.setattr(predictor, "newton", failing)
    skipped = prob.solve(bc.SolverOptions(predictor="coarse"), steps=steps[:2])
    none = prob.solve(bc.SolverOptions(predictor="none"), steps=steps[:2])
    assert [s.iterations for s in skipped.steps] == [s.iterations for s in none.steps]
    assert all(s.coarse_iterations > 0 for s in skipped.steps)
    np.testing.assert_allclose(skipped.contact_force, none.contact_force, rtol=0,
                               atol=1e-12 * abs(none.normal_force))


def test_levels_stop_at_the_smallest_frame(two_blocks):
    """No coarse level from a frame of at most COARSE_MIN nodes; levels of
    about a quarter of the nodes each down to it."""
    system = two_blocks
    points = system.frame.points[system.act]
    assert system.m <= predictor.COARSE_MIN and Predictor(system, points).levels == []
    p = Predictor(system, points, min_nodes=4)
    assert p.sizes and p.sizes[-1] <= 4 < system.m
    assert all(2 * b <= a for a, b in zip([system.m] + p.sizes, p.sizes))


def test_predictor_option_is_checked():
    with pytest.raises(bc.ConfigError, match="predictor"):
        bc.SolverOptions(predictor="multigrid")
