"""The a-posteriori verification of contact solutions (verification.py)
and the round-off-free singular diagnosis of a body free to slide.

Each check is shown to catch one perturbed node of a solved problem, with
its message naming that node, while the unperturbed solution passes."""

import copy

import numpy as np
import pytest

import bemcontact as bc
from bemcontact.contact import law
from bemcontact.contact.kinematics import ROUNDOFF, drop_roundoff
from bemcontact.contact.verification import CHECKS, EPS, SMALL, verify

E, NU = 1e4, 0.3


def _cubes(top=(0.0, 0.0, -0.04), mu=0.1, nl=2, nu_=3):
    """Two 2 mm cubes, the lower clamped, the upper's top face displaced."""
    lower = bc.ElasticBody(bc.box((0, 0, 0), (2, 2, 2), nl), bc.LinearElastic(E, NU),
                           {"zmin": bc.Fixed()}, name="lower")
    upper = bc.ElasticBody(bc.box((0, 0, 2), (2, 2, 4), nu_), bc.LinearElastic(E, NU),
                           {"zmax": bc.Displacement(top)}, name="upper")
    return bc.ContactProblem(lower, upper, bc.ContactPair("zmax", "zmin", mu))


@pytest.fixture(scope="module")
def solved():
    return _cubes().solve(bc.SolverOptions(progress=False))


def test_the_solution_passes_every_check_with_margin(solved):
    v = solved.verification
    assert v is not None and v.passed, v.message()
    assert list(v.checks) == list(CHECKS)
    # the frame conditions hold to the Newton tolerance (1e-10), four orders
    # inside their tolerance (1e-6 of the scales)
    for name in ("penetration", "tension", "complementarity", "cone", "frame_equilibrium"):
        assert v.checks[name].ratio < 1e-2, (name, v.checks[name])
    s = solved.summary()["verification"]
    assert s["passed"] is True and set(s["checks"]) == set(CHECKS)
    assert s["checks"]["small_displacements"]["value"] == pytest.approx(0.04, rel=1e-6)


def _interior(result):
    """A closed frame node with pressure (not on the frame's border)."""
    fr = result.frame
    j = int(np.argmax(fr.pressure))
    assert fr.pressure[j] > 0
    return j


def _failed(result, name):
    v = verify(result)
    assert not v.passed
    assert v.failed[0].name == name, v.message()
    return v


def test_penetration_is_caught_at_its_node(solved):
    r = copy.deepcopy(solved)
    j = _interior(r)
    r.frame.gap[j] = -1e-4  # 0.1 um into the other body, at a pressed node
    v = _failed(r, "penetration")
    assert f"node {j} " in v.message() and "gap -0.0001" in v.message()
    assert v.failed[0].location["node"] == j
    assert v.failed[0].location["point"] == pytest.approx(list(r.frame.points[j]))


def test_tension_is_caught(solved):
    r = copy.deepcopy(solved)
    j = _interior(r)
    r.frame.pressure[j] = -0.01 * solved.frame.pressure.max()
    v = _failed(r, "tension")
    assert f"node {j} " in v.message()


def test_complementarity_is_caught(solved):
    r = copy.deepcopy(solved)
    j = _interior(r)
    r.frame.gap[j] = 1e-3  # open while pressed
    v = _failed(r, "complementarity")
    assert f"node {j} " in v.message()


def test_traction_outside_the_cone_is_caught(solved):
    r = copy.deepcopy(solved)
    j = _interior(r)
    p = r.frame.pressure[j]
    r.frame.tangential_traction[j] = [1.5 * 0.1 * p, 0.0, 0.0]  # |q| = 1.5 mu p
    v = _failed(r, "cone")
    assert f"node {j} " in v.message()


def test_slip_in_the_direction_of_the_traction_is_caught(solved):
    r = copy.deepcopy(solved)
    j = _interior(r)
    p = r.frame.pressure[j]
    q = np.array([0.1 * p, 0.0, 0.0])  # on the cone
    r.frame.tangential_traction[j] = q
    r.frame.state[j] = law.SLIP
    r.frame.slip_increment[j] = [1e-3, 0.0, 0.0]  # along q: friction would drive the slip
    v = _failed(r, "slip_direction")
    assert f"node {j} " in v.message()
    # the same slip against the traction passes
    r.frame.slip_increment[j] = [-1e-3, 0.0, 0.0]
    assert verify(r).passed, verify(r).message()


def test_contact_tractions_that_do_not_carry_the_frames_force_are_caught(solved):
    r = copy.deepcopy(solved)
    i = r.interfaces[1]
    k = int(i.nodes[np.argmax(np.linalg.norm(i.traction, axis=1))])
    r.bodies[1].traction[k] *= 1.01  # one contact node's recovered traction off by 1 %
    v = _failed(r, "frame_equilibrium")
    assert "body upper's contact surfaces" in v.message()


def test_a_frame_that_loses_force_is_caught(solved):
    r = copy.deepcopy(solved)
    pair = r.pairs[0]
    assert pair.untransmitted < 1e-9 * np.abs(pair.transmitted).max()  # mortar, same surfaces
    pair.transmitted[1] *= 1.001  # body 2 receives 0.1 % more than body 1 gives
    r.bodies[1].traction[pair.interfaces[1].nodes] *= 1.001
    v = _failed(r, "frame_equilibrium")
    assert "pair lower:zmax/upper:zmin" in v.message()


def test_an_unbalanced_body_is_caught(solved):
    r = copy.deepcopy(solved)
    b = r.bodies[1]
    total = float(np.abs(b.weights) @ np.linalg.norm(b.traction, axis=1))
    b.traction[0] += [0.0, 0.1 * total / b.weights[0], 0.0]  # a tenth of its forces, unbalanced
    v = _failed(r, "body_equilibrium")
    assert "body upper" in v.message()


def test_a_body_moved_clear_of_the_contact_is_verified():
    """The upper cube lifted 0.04 off the lower: every node open, no force
    anywhere, and the round-off of its tractions (1e-13 against loads of
    none) is no unbalance; a tenth of the forces its lift would cause at
    the contact's stiffness is still caught."""
    res = _cubes(top=(0.0, 0.0, 0.04)).solve(bc.SolverOptions(progress=False))
    assert res.converged and res.verification.passed
    assert np.nanmin(res.pairs[0].frame.gap) > 0.03  # open everywhere
    assert abs(res.normal_force) <= 1e-9
    r = copy.deepcopy(res)
    b = r.bodies[1]
    b.traction[0] += [0.0, 0.0, 1e-3 * E * 0.04 / b.weights[0]]
    assert "body upper" in _failed(r, "body_equilibrium").message()


def test_a_huge_rigid_motion_is_caught(solved):
    r = copy.deepcopy(solved)
    b = r.bodies[1]
    b.displacement[:, 0] += 2e15
    v = _failed(r, "small_displacements")
    assert "body upper node" in v.message() and "2e+15" in v.message()
    size = np.linalg.norm(np.ptp(b.points, axis=0))
    assert v.failed[0].tolerance == pytest.approx(SMALL * size)


def test_drop_roundoff_zeroes_only_what_is_round_off():
    M = np.array([[1.0, 3e-17, 0.5], [2e-10, 1.0, -4e-17], [0.3, 2.0, 1.0]])
    out = drop_roundoff(M.copy())  # per column
    assert out[1, 0] == 2e-10 and out[0, 1] == 0.0 and out[1, 2] == 0.0
    assert out[0, 0] == 1.0 and out[2, 1] == 2.0
    rows = drop_roundoff(np.array([[1.0, 0.5 * ROUNDOFF, 2 * ROUNDOFF]]), axis=1)
    assert rows.tolist() == [[1.0, 0.0, 2 * ROUNDOFF]]


def test_a_cube_free_to_slide_is_singular_whatever_the_round_off(monkeypatch):
    """The failure seen on one processor, reproduced on any: the upper cube,
    frictionless and held only in z, may slide and turn about z; round-off
    of 1e-16 in its sliding modes' normal components (the size it had
    there) made the first increment's penalty balance move it by 2e15 mm,
    and every node opened with a zero residual.  With the noise injected the
    solve must still end in the singular diagnosis."""
    real = bc.ElasticBody.condense
    rng = np.random.default_rng(1)

    def noisy(body, *args, **kwargs):
        c = real(body, *args, **kwargs)
        if c.Rf.shape[1]:
            z = c.dofs[2::3]  # the normal (z) components at the contact nodes
            scale = np.abs(c.Rf).max(axis=0)
            c.Rf[z] += 1e-16 * scale * rng.standard_normal((z.size, c.Rf.shape[1]))
            c.known_modal_force += 1e-16 * rng.standard_normal(c.known_modal_force.shape)
        return c

    monkeypatch.setattr(bc.ElasticBody, "condense", noisy)
    prob = _cubes(top=(None, None, -0.04), mu=0.0, nl=1, nu_=1)
    with pytest.raises(bc.ConvergenceError, match="singular") as info:
        prob.solve(bc.SolverOptions(progress=False))
    r = info.value.result
    assert r.converged is False
    assert max(np.abs(b.displacement).max() for b in r.bodies) < 1.0  # no 2e15 slide


def test_a_penetrating_answer_called_converged_is_refused(monkeypatch):
    """Whatever makes Newton stop on a wrong state, the verification turns it
    into a non-converged solve naming the check: here Newton is made to
    accept its starting point (every node open, the cube pushed 0.04 mm into
    the other)."""
    from bemcontact.contact import increment
    from bemcontact.contact.results import StepRecord

    def accept_the_start(system, z, *args, **kwargs):
        return z, StepRecord(1.0, 0, [0.0], True), None

    monkeypatch.setattr(increment, "newton", accept_the_start)
    with pytest.raises(bc.ConvergenceError, match="verification failed: penetration") as info:
        _cubes().solve(bc.SolverOptions(progress=False, predictor="none"))
    assert info.value.result.converged is False
    assert info.value.result.verification.checks["penetration"].ratio > 1 / EPS
