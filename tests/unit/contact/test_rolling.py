"""Rolling on the full path (contact/rolling.py FrameRolling and the rolling
rows of contact/interface.py): the upwind interpolation on unstructured
frame nodes, and a rolling solve's limits that hold exactly whatever the
discretization: full sliding under a large creepage (|F| = mu F_n, opposite
to it) and under a large spin (every traction mu p_n against the rigid
slip); transient rolling by whole upwind steps ends at the steady state."""

from __future__ import annotations

import dataclasses
import pathlib

import numpy as np
import pytest

from bemcontact.contact import Rolling
from bemcontact.contact.law import OPEN
from bemcontact.contact.rolling import FrameRolling
from bemcontact.errors import ConfigError


def scattered(n=400, seed=0):
    rng = np.random.default_rng(seed)
    xy = rng.uniform(-1.0, 1.0, (n, 2))
    pts = np.column_stack([xy, np.zeros(n)])
    Q = np.broadcast_to(np.eye(3), (n, 3, 3)).copy()
    return pts, Q


def test_the_upwind_interpolation_is_exact_on_linear_fields_and_zero_upstream():
    pts, Q = scattered()
    n = len(pts)
    fr = FrameRolling(Rolling((1, 0, 0), mode="transient", distance=0.05), pts, Q,
                      np.full(n, 0.1), np.ones(n), np.zeros(n, dtype=int))
    u = np.column_stack([2.0 + 3.0 * pts[:, 0] - pts[:, 1], 0.5 * pts[:, 1]])
    Su = fr.shift(u)
    centre = pts[:, :2].mean(axis=0)
    x_up = pts[:, 0] + 0.05
    inside = np.abs(Su).sum(axis=1) > 0
    want = np.column_stack([2.0 + 3.0 * x_up - pts[:, 1], 0.5 * pts[:, 1]])
    assert inside.sum() > 0.9 * n
    assert np.abs(Su[inside] - want[inside]).max() < 1e-12
    import scipy.spatial

    outside = scipy.spatial.Delaunay(pts[:, :2]).find_simplex(
        np.column_stack([x_up, pts[:, 1]])) < 0
    assert np.array_equal(~inside, outside)  # zero exactly where upstream leaves the nodes' hull
    # the rigid slip of a spin about the area centroid: w = phi (-y, x)
    sp = FrameRolling(Rolling((1, 0, 0), (0.1, 0.2), 0.3), pts, Q, np.full(n, 0.1),
                      np.ones(n), np.zeros(n, dtype=int))
    rel = pts[:, :2] - centre
    assert np.allclose(sp.w, np.column_stack([0.1 - 0.3 * rel[:, 1], 0.2 + 0.3 * rel[:, 0]]),
                       atol=1e-14)


def test_tangential_vectors_are_rotated_between_local_bases():
    """Nodes whose local bases are turned by different angles about n: the
    shift of a uniform global vector field is that field in each node's own
    basis (to 1e-12 where the upstream point is inside)."""
    pts, _ = scattered(300, seed=1)
    n = len(pts)
    ang = np.random.default_rng(2).uniform(0, 2 * np.pi, n)
    Q = np.zeros((n, 3, 3))
    Q[:, 0, 0], Q[:, 1, 0] = np.cos(ang), np.sin(ang)  # columns t1, t2, n
    Q[:, 0, 1], Q[:, 1, 1] = -np.sin(ang), np.cos(ang)
    Q[:, 2, 2] = 1.0
    fr = FrameRolling(Rolling((0, 1, 0), mode="transient", distance=0.03), pts, Q,
                      np.full(n, 0.1), np.ones(n), np.zeros(n, dtype=int))
    g = np.array([0.7, -0.2])
    local = np.einsum("nji,j->ni", Q[:, :2, :2], g)
    S = fr.shift(local)
    inside = np.abs(S).sum(axis=1) > 0
    assert inside.sum() > 0.9 * n
    assert np.abs(S[inside] - local[inside]).max() < 1e-12
    with pytest.raises(ConfigError, match="not tangent"):
        FrameRolling(Rolling((0, 0, 1)), pts, Q, np.full(n, 0.1), np.ones(n),
                     np.zeros(n, dtype=int))


EXAMPLE = pathlib.Path(__file__).parents[3] / "examples" / "rolling_ball_multiscale.toml"


@pytest.fixture(scope="module")
def full_problem():
    """The rolling example's coarse bodies on the full path (its frame:
    201 nodes), pressed and rolled."""
    import bemcontact as bc

    pf = bc.load_problem(EXAMPLE)
    return pf.contact_problem(), list(pf.steps)


def solve(full_problem, rolling):
    problem, steps = full_problem
    steps = [steps[0], dataclasses.replace(steps[1], rolling=rolling)]
    return problem.solve(steps=steps)


def test_full_sliding_under_a_large_creepage(full_problem):
    """xi = -100 (the rigid slip 2,500 times the elastic one, p/E*): every
    closed node slips, |F_x| = mu F_n to 1e-6 and F_x opposes the creepage
    (F_x > 0 on the second body); the creep force is the frame's resultant."""
    r = solve(full_problem, Rolling((1, 0, 0), (-100.0, 0.0)))
    roll = r.rolling
    assert r.converged
    assert roll["creep_force_ratio"][0] == pytest.approx(1.0, abs=1e-6)
    assert abs(roll["creep_force_ratio"][1]) < 1e-6
    assert roll["adhesion_area"] == 0.0 and roll["slip_area"] > 0.0
    assert roll["creep_force"][0] == pytest.approx(r.contact_force[0], rel=1e-9)
    # the frame's micro-slip is the rigid slip (xi, 0) to 1 % (the elastic part is
    # 1/2500 of it), the traction against it: the power density is > 0 where it slips
    fr = r.frame
    slip = fr.state == 2
    assert np.all(fr.microslip[slip, 0] < 0.0)
    assert np.allclose(fr.microslip[slip, 0], -100.0, rtol=1e-2)
    assert np.all(fr.power_density[slip] > 0.0) and not fr.power_density[~slip].any()


def test_full_sliding_under_a_large_spin(full_problem):
    """phi = 1000 rad/mm (the rigid slip 1e4 times the elastic one, p/E*):
    every closed node's traction is mu p_n against the rigid slip
    phi (-y, x) about the rolling frame's origin (the first touch) to 1e-3
    of mu p_n."""
    r = solve(full_problem, Rolling((1, 0, 0), (0.0, 0.0), 1000.0))
    fr = r.frame
    closed = (fr.state != OPEN) & (fr.weights > 0)
    p = fr.pressure[closed]
    xy = fr.points[closed, :2] - np.array(r.rolling["origin"][:2])  # the first touch
    rho = np.hypot(xy[:, 0], xy[:, 1])
    far = rho > 0.05  # the direction is defined away from the centre
    t = fr.tangential_traction[closed][far, :2]
    want = -0.3 * p[far, None] * np.column_stack([-xy[far, 1], xy[far, 0]]) / rho[far, None]
    assert np.abs(t - want).max() < 1e-3 * 0.3 * p.max()
    # only at the spin's centre (zero rigid slip there) may a node stick: within a
    # coarse element (0.5 mm) of it
    stuck = fr.points[fr.state == 1, :2] - np.array(r.rolling["origin"][:2])
    assert np.all(np.hypot(stuck[:, 0], stuck[:, 1]) < 0.75)
